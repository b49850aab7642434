#include "plimsoll/geometry/uv_layout.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <unordered_map>

namespace plimsoll {

UvPlacement fitUvsIntoUnitSquare(const TriangleMesh& mesh) {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300);
    Eigen::Vector2d hi = Eigen::Vector2d::Constant(-1e300);
    for (const auto& uv : mesh.uvs) {
        lo = lo.cwiseMin(uv);
        hi = hi.cwiseMax(uv);
    }
    UvPlacement placement;
    if (mesh.uvs.empty() || (lo.minCoeff() >= 0.0 && hi.maxCoeff() <= 1.0)) return placement;
    const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
    placement.scale = extent > 0 ? 1.0 / extent : 1.0;
    placement.offset = -placement.scale * lo;
    return placement;
}

namespace {

// Vertex ids equal exactly when position and UV are equal (vertices split only by normals
// join again).
std::vector<std::uint32_t> weldByPositionAndUv(const TriangleMesh& mesh) {
    using Key = std::array<double, 5>;
    std::vector<Key> keys(mesh.vertexCount());
    for (std::size_t v = 0; v < keys.size(); ++v) {
        const Eigen::Vector3d& p = mesh.positions[v];
        const Eigen::Vector2d& uv = mesh.uvs[v];
        keys[v] = {p.x(), p.y(), p.z(), uv.x(), uv.y()};
    }
    std::vector<std::uint32_t> order(keys.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    std::vector<std::uint32_t> id(keys.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        const bool sameAsPrevious = i > 0 && keys[order[i]] == keys[order[i - 1]];
        id[order[i]] = sameAsPrevious ? id[order[i - 1]] : order[i];
    }
    return id;
}

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

}  // namespace

std::vector<std::uint32_t> uvIslands(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> vertex = weldByPositionAndUv(mesh);
    std::vector<std::uint32_t> parent(mesh.triangleCount());
    std::iota(parent.begin(), parent.end(), 0u);
    std::unordered_map<std::uint64_t, std::uint32_t> firstUse;
    firstUse.reserve(3 * mesh.triangleCount());
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = vertex[mesh.triangles[t][k]];
            const std::uint32_t b = vertex[mesh.triangles[t][(k + 1) % 3]];
            const std::uint64_t edge =
                (std::uint64_t{std::min(a, b)} << 32) | std::uint64_t{std::max(a, b)};
            auto [it, inserted] = firstUse.try_emplace(edge, t);
            if (!inserted) {
                // Union by smaller index keeps each root the island's smallest triangle.
                const std::uint32_t ra = findRoot(parent, it->second), rb = findRoot(parent, t);
                parent[std::max(ra, rb)] = std::min(ra, rb);
            }
        }
    }
    for (std::uint32_t t = 0; t < parent.size(); ++t) parent[t] = findRoot(parent, t);
    return parent;
}

}  // namespace plimsoll
