// The one translation unit that includes CGAL (graph.h segmentMeshSdf): Shape Diameter
// Function per facet and graph-cut segmentation (Shapira, Shamir, Cohen-Or 2008; CGAL's
// "Triangulated Surface Mesh Segmentation", CGAL::sdf_values and
// CGAL::segmentation_from_sdf_values), as paper section 4.1 uses it. CGAL is slow to compile
// (about 30 s): everything else about automatic graphs is in graph_auto.cpp.
#include "plimsoll/graph/graph.h"
#include "plimsoll/graph_auto/graph_auto.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/mesh_segmentation.h>

#include <chrono>

namespace plimsoll {

bool meshSegmentationAvailable() { return true; }

Result<MeshSegmentation> segmentMeshSdf(const TriangleMesh& input, int clusters,
                                        const std::function<void(double)>& progress) {
    using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
    using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
    using Face = Mesh::Face_index;
    using Vertex = Mesh::Vertex_index;
    const auto start = std::chrono::steady_clock::now();
    if (clusters < 1)
        return makeError(ErrorKind::invalidArgument,
                         input.source + ": segmentation needs at least 1 segment");
    if (input.triangles.empty())
        return makeError(ErrorKind::invalidArgument, input.source + ": the mesh has no triangles");

    // Vertices split at UV seams are welded back, so the surface is one connected manifold.
    const std::vector<std::uint32_t> weld = weldByPosition(input);
    Mesh mesh;
    std::vector<Vertex> vertexOf(input.positions.size());
    for (std::size_t i = 0; i < input.positions.size(); ++i) {
        if (weld[i] != i) continue;
        const Eigen::Vector3d& p = input.positions[i];
        vertexOf[i] = mesh.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z()));
    }
    for (std::size_t t = 0; t < input.triangles.size(); ++t) {
        const Triangle& tri = input.triangles[t];
        const Face f =
            mesh.add_face(vertexOf[weld[tri[0]]], vertexOf[weld[tri[1]]], vertexOf[weld[tri[2]]]);
        if (f == Mesh::null_face()) {
            return makeError(ErrorKind::invalidArgument,
                             input.source + ": triangle " + std::to_string(t) +
                                 " makes the surface non-manifold (or is degenerate): the "
                                 "segmentation needs a closed manifold mesh");
        }
    }
    if (progress) progress(0.05);

    auto sdf = mesh.add_property_map<Face, double>("f:sdf").first;
    // Default cone (2/3 pi) and ray count (25), post-processed (normalised, smoothed).
    CGAL::sdf_values(mesh, sdf);
    if (progress) progress(0.7);
    auto segment = mesh.add_property_map<Face, std::size_t>("f:segment").first;
    // Clusters of SDF values by a soft graph cut; each connected part of a cluster is a
    // segment.
    const std::size_t count =
        CGAL::segmentation_from_sdf_values(mesh, sdf, segment, static_cast<std::size_t>(clusters));
    if (progress) progress(0.95);

    MeshSegmentation result;
    result.segmentCount = static_cast<int>(count);
    result.triangleSegment.resize(input.triangles.size());
    // Faces were added in triangle order, so face index = triangle index.
    for (Face f : mesh.faces()) {
        result.triangleSegment[static_cast<std::size_t>(f.idx())] = static_cast<int>(segment[f]);
    }
    result.sdfSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace plimsoll
