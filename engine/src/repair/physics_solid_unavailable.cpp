// A build without CGAL (PLIMSOLL_WITH_CGAL=OFF): the repair says it is not there.
#include "plimsoll/repair/physics_solid.h"

#include "close_openings.h"

namespace plimsoll {

bool repairAvailable() { return false; }

Result<PhysicsSolid> buildPhysicsSolid(const TriangleMesh& surface, const RepairSettings&) {
    return makeError(ErrorKind::unsupported,
                     surface.source +
                         ": the surface is not one closed solid, and this build has no "
                         "mesh repair (built without CGAL: PLIMSOLL_WITH_CGAL=OFF)");
}

Status closeOpenings(PhysicsSolid& solid, const std::vector<Basin>&, const RepairSettings&) {
    return makeError(ErrorKind::unsupported,
                     solid.mesh.source +
                         ": closing openings needs mesh repair, "
                         "and this build has none (PLIMSOLL_WITH_CGAL=OFF)");
}

}  // namespace plimsoll
