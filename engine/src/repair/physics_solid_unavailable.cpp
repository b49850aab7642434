// A build without CGAL (PLIMSOLL_WITH_CGAL=OFF): the repair says it is not there.
#include "plimsoll/repair/physics_solid.h"

namespace plimsoll {

bool repairAvailable() { return false; }

Result<PhysicsSolid> buildPhysicsSolid(const TriangleMesh& surface, const RepairSettings&) {
    return makeError(ErrorKind::unsupported,
                     surface.source + ": the surface is not one closed solid, and this build has no "
                                      "mesh repair (built without CGAL: PLIMSOLL_WITH_CGAL=OFF)");
}

}  // namespace plimsoll
