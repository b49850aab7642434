// The choice between the artist's mesh and its physics solid (physics_solid.h); the repair
// itself is in physics_solid_cgal.cpp.
#include "plimsoll/repair/physics_solid.h"

#include "close_openings.h"

#include "plimsoll/physics/massprops.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <array>
#include <map>
#include <numeric>
#include <sstream>
#include <vector>

namespace plimsoll {

namespace {

/// True when two of the surface's parts (connected through shared positions, so that UV
/// seams do not split a part) each enclose volume and their boxes overlap: closed parts that
/// may overlap (a barrel's hoops on its body, nested shells), whose volumes a sum would count
/// twice. A part that encloses negative volume (the inner wall of a hollow solid) is not one.
bool hasOverlappingSolidParts(const TriangleMesh& surface) {
    std::map<std::array<double, 3>, std::uint32_t> idOf;
    std::vector<std::uint32_t> vertexId(surface.positions.size());
    for (std::size_t v = 0; v < surface.positions.size(); ++v) {
        const Eigen::Vector3d& p = surface.positions[v];
        vertexId[v] =
            idOf.try_emplace({p.x(), p.y(), p.z()}, std::uint32_t(idOf.size())).first->second;
    }
    std::vector<std::uint32_t> parent(idOf.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const Triangle& t : surface.triangles) {
        const std::uint32_t a = find(vertexId[t[0]]);
        parent[find(vertexId[t[1]])] = a;
        parent[find(vertexId[t[2]])] = a;
    }
    struct Part {
        double volume = 0;
        Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
        Eigen::Vector3d max = Eigen::Vector3d::Constant(std::numeric_limits<double>::lowest());
    };
    std::map<std::uint32_t, Part> parts;
    for (const Triangle& t : surface.triangles) {
        Part& part = parts[find(vertexId[t[0]])];
        const Eigen::Vector3d& a = surface.positions[t[0]];
        const Eigen::Vector3d& b = surface.positions[t[1]];
        const Eigen::Vector3d& c = surface.positions[t[2]];
        part.volume += a.dot(b.cross(c)) / 6.0;
        for (const Eigen::Vector3d* p : {&a, &b, &c}) {
            part.min = part.min.cwiseMin(*p);
            part.max = part.max.cwiseMax(*p);
        }
    }
    std::vector<const Part*> solids;
    for (const auto& [root, part] : parts)
        if (part.volume > 0) solids.push_back(&part);
    for (std::size_t i = 0; i < solids.size(); ++i)
        for (std::size_t j = i + 1; j < solids.size(); ++j)
            if ((solids[i]->min.array() < solids[j]->max.array()).all() &&
                (solids[j]->min.array() < solids[i]->max.array()).all())
                return true;
    return false;
}

}  // namespace

Result<PhysicsSolid> physicsSolidFor(const TriangleMesh& surface, const ValidationReport& report,
                                     const RepairSettings& settings) {
    bool solidAsIs = true;
    for (const Problem& p : report.problems)
        if (p.severity == Severity::Error && !isUvProblem(p.kind) &&
            p.kind != ProblemKind::MissingUvs)
            solidAsIs = false;
    PhysicsSolid solid;
    if (!solidAsIs || hasOverlappingSolidParts(surface)) {
        Result<PhysicsSolid> built = buildPhysicsSolid(surface, settings);
        if (!built) return built.error();
        solid = std::move(*built);
    } else {
        solid.mesh = surface;
        solid.materialVolume = exactSolidMassProperties(surface, 1.0).volume;
        solid.displacementVolume = solid.materialVolume;
    }
    if (settings.closeOpenings && repairAvailable()) {
        const std::vector<Basin> basins =
            findBasins(solid.mesh, solid.materialVolume, settings.basins);
        if (Status s = closeOpenings(solid, basins, settings); !s) return s.error();
    }
    return solid;
}

MassProperties hollowSpace(const std::vector<Opening>& openings) {
    MassProperties hollow;
    for (const Opening& opening : openings)
        hollow = hollow.mass > 0 ? hollow + opening.cavity : opening.cavity;
    return hollow;
}

std::string describeRepairs(const std::vector<Repair>& repairs) {
    if (repairs.empty()) return "none";
    std::ostringstream text;
    for (std::size_t i = 0; i < repairs.size(); ++i)
        text << (i ? ", " : "") << repairs[i].kind << " " << repairs[i].count;
    return text.str();
}

}  // namespace plimsoll
