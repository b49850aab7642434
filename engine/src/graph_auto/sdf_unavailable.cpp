// A build without CGAL (PLIMSOLL_WITH_CGAL=OFF): the SDF segmentation that automatic water
// graphs start from is not there, and asking for it says so.
#include "plimsoll/graph/graph.h"
#include "plimsoll/graph_auto/graph_auto.h"

namespace plimsoll {

bool meshSegmentationAvailable() { return false; }

Result<MeshSegmentation> segmentMeshSdf(const TriangleMesh& mesh, int,
                                        const std::function<void(double)>&) {
    return makeError(ErrorKind::unsupported,
                     mesh.source +
                         ": automatic water graphs need CGAL's mesh segmentation, "
                         "and this build has none (configured with PLIMSOLL_WITH_CGAL=OFF)");
}

}  // namespace plimsoll
