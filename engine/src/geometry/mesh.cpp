#include "plimsoll/geometry/mesh.h"

#include <Eigen/Geometry>

#include <cstring>
#include <unordered_map>

namespace plimsoll {

namespace {
struct PositionHash {
    std::size_t operator()(const Eigen::Vector3d& p) const {
        std::size_t h = 1469598103934665603ull;
        for (int k = 0; k < 3; ++k) {
            double v = p[k] == 0.0 ? 0.0 : p[k];  // -0 and +0 weld together
            std::uint64_t bits;
            std::memcpy(&bits, &v, sizeof bits);
            h = (h ^ bits) * 1099511628211ull;
        }
        return h;
    }
};
struct PositionEqual {
    bool operator()(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const { return a == b; }
};
}  // namespace

std::vector<std::uint32_t> weldByPosition(const TriangleMesh& mesh) {
    std::unordered_map<Eigen::Vector3d, std::uint32_t, PositionHash, PositionEqual> first;
    first.reserve(mesh.positions.size());
    std::vector<std::uint32_t> id(mesh.positions.size());
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
        id[v] = first.try_emplace(mesh.positions[v], v).first->second;
    }
    return id;
}

Bounds3 computeBounds(const TriangleMesh& mesh) {
    Bounds3 b;
    for (const auto& p : mesh.positions) {
        b.min = b.min.cwiseMin(p);
        b.max = b.max.cwiseMax(p);
    }
    return b;
}

Eigen::Vector3d triangleAreaVector(const TriangleMesh& mesh, const Triangle& t) {
    const Eigen::Vector3d& a = mesh.positions[t[0]];
    return 0.5 * (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a);
}

double triangleUvArea(const TriangleMesh& mesh, const Triangle& t) {
    const Eigen::Vector2d e1 = mesh.uvs[t[1]] - mesh.uvs[t[0]];
    const Eigen::Vector2d e2 = mesh.uvs[t[2]] - mesh.uvs[t[0]];
    return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

}  // namespace plimsoll
