// The choice between the artist's mesh and its physics solid (physics_solid.h); the repair
// itself is in physics_solid_cgal.cpp.
#include "plimsoll/repair/physics_solid.h"

#include "plimsoll/physics/massprops.h"

#include <sstream>

namespace plimsoll {

Result<PhysicsSolid> physicsSolidFor(const TriangleMesh& surface, const ValidationReport& report,
                                     const RepairSettings& settings) {
    bool solidAsIs = true;
    for (const Problem& p : report.problems)
        if (p.severity == Severity::Error && !isUvProblem(p.kind) && p.kind != ProblemKind::MissingUvs)
            solidAsIs = false;
    if (!solidAsIs) return buildPhysicsSolid(surface, settings);
    PhysicsSolid solid;
    solid.mesh = surface;
    solid.materialVolume = exactSolidMassProperties(surface, 1.0).volume;
    solid.displacementVolume = solid.materialVolume;
    return solid;
}

std::string describeRepairs(const std::vector<Repair>& repairs) {
    if (repairs.empty()) return "none";
    std::ostringstream text;
    for (std::size_t i = 0; i < repairs.size(); ++i)
        text << (i ? ", " : "") << repairs[i].kind << " " << repairs[i].count;
    return text.str();
}

}  // namespace plimsoll
