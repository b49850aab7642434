// Moving painted maps between parameterisations (map_transfer.h).
#include "plimsoll/surface/map_transfer.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <string>

namespace plimsoll {

namespace {

using Vec3 = Eigen::Vector3d;

// Closest point of triangle (a, b, c) to p, as barycentric coordinates (Ericson, Real-Time
// Collision Detection, 5.1.5: the Voronoi regions of the corners, then of the edges).
Vec3 closestBarycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return {1 - v, v, 0};
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return {1 - w, 0, w};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {0, 1 - w, w};
    }
    const double denominator = va + vb + vc;
    if (!(std::abs(denominator) > 0)) return {1, 0, 0};  // degenerate: its first corner
    const double v = vb / denominator, w = vc / denominator;
    return {1 - v - w, v, w};
}

Vec3 corner(const TriangleMesh& mesh, std::uint32_t t, int k) {
    return mesh.positions[mesh.triangles[t][static_cast<std::size_t>(k)]];
}

Eigen::Vector2d interpolatedUv(const TriangleMesh& mesh, std::uint32_t t, const Vec3& b) {
    const Triangle& tri = mesh.triangles[t];
    return b[0] * mesh.uvs[tri[0]] + b[1] * mesh.uvs[tri[1]] + b[2] * mesh.uvs[tri[2]];
}

bool sameSurface(const TriangleMesh& a, const TriangleMesh& b) {
    if (a.triangleCount() != b.triangleCount()) return false;
    for (std::uint32_t t = 0; t < a.triangleCount(); ++t) {
        for (int k = 0; k < 3; ++k) {
            if (corner(a, t, k) != corner(b, t, k)) return false;
        }
    }
    return true;
}

/// Calls visit(texel index, barycentric coordinates of the nearest point, distance in texels)
/// for every texel of a width x height map whose centre is within one texel of triangle t's UVs
/// (the partly covered texels and a ring around them). Texel (x, row) has its centre at uv
/// ((x + 0.5) / width, 1 - (row + 0.5) / height).
template <class Visit>
void forTexelsNear(const TriangleMesh& mesh, std::uint32_t t, int width, int height,
                   Visit&& visit) {
    const auto toTexels = [&](const Eigen::Vector2d& uv) {
        return Vec3(uv.x() * width - 0.5, (1.0 - uv.y()) * height - 0.5, 0.0);
    };
    const Triangle& tri = mesh.triangles[t];
    const Vec3 a = toTexels(mesh.uvs[tri[0]]), b = toTexels(mesh.uvs[tri[1]]),
               c = toTexels(mesh.uvs[tri[2]]);
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))) - 1);
    const int x1 =
        std::min(width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))) + 1);
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))) - 1);
    const int y1 =
        std::min(height - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))) + 1);
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            const Vec3 q(x, y, 0.0);
            const Vec3 bary = closestBarycentric(q, a, b, c);
            const double d = (bary[0] * a + bary[1] * b + bary[2] * c - q).norm();
            if (d <= 1.0) visit(static_cast<std::size_t>(y) * width + x, bary, d);
        }
    }
}

}  // namespace

// ---------------------------------------------------------------------------------------------

struct SurfaceLocator::Grid {
    const TriangleMesh* mesh = nullptr;
    Vec3 origin = Vec3::Zero();
    double cell = 1;
    Eigen::Vector3i cells = Eigen::Vector3i::Ones();
    std::vector<std::size_t> start;  // cell c holds items[start[c] .. start[c + 1])
    std::vector<std::uint32_t> items;

    Eigen::Vector3i cellOf(const Vec3& p) const {
        Eigen::Vector3i c;
        for (int k = 0; k < 3; ++k) {
            c[k] = std::clamp(static_cast<int>(std::floor((p[k] - origin[k]) / cell)), 0,
                              cells[k] - 1);
        }
        return c;
    }
    std::size_t index(const Eigen::Vector3i& c) const {
        return static_cast<std::size_t>(c.x()) +
               static_cast<std::size_t>(cells.x()) *
                   (static_cast<std::size_t>(c.y()) + static_cast<std::size_t>(cells.y()) * c.z());
    }
};

SurfaceLocator::SurfaceLocator(const TriangleMesh& mesh) : grid_(std::make_unique<Grid>()) {
    Grid& g = *grid_;
    g.mesh = &mesh;
    const Bounds3 bounds = computeBounds(mesh);
    const Vec3 extent = (bounds.max - bounds.min).cwiseMax(1e-12);
    // About two triangles per cell along each axis: cell volume from the triangle count.
    const double n = std::max<double>(1.0, static_cast<double>(mesh.triangleCount()));
    g.cell = std::max(std::cbrt(extent.prod() / n) * 1.5, extent.maxCoeff() / 256.0);
    g.origin = bounds.min;
    for (int k = 0; k < 3; ++k) {
        g.cells[k] = std::max(1, static_cast<int>(std::ceil(extent[k] / g.cell)));
    }
    const std::size_t cellCount = static_cast<std::size_t>(g.cells.prod());
    g.start.assign(cellCount + 1, 0);
    const auto forCells = [&](std::uint32_t t, auto visit) {
        Eigen::AlignedBox3d box;
        for (int k = 0; k < 3; ++k) box.extend(corner(mesh, t, k));
        const Eigen::Vector3i lo = g.cellOf(box.min()), hi = g.cellOf(box.max());
        for (int z = lo.z(); z <= hi.z(); ++z)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int x = lo.x(); x <= hi.x(); ++x) visit(g.index({x, y, z}));
    };
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        forCells(t, [&](std::size_t c) { ++g.start[c + 1]; });
    }
    for (std::size_t c = 0; c < cellCount; ++c) g.start[c + 1] += g.start[c];
    g.items.resize(g.start.back());
    std::vector<std::size_t> cursor(g.start.begin(), g.start.end() - 1);
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        forCells(t, [&](std::size_t c) { g.items[cursor[c]++] = t; });
    }
}

SurfaceLocator::~SurfaceLocator() = default;
SurfaceLocator::SurfaceLocator(SurfaceLocator&&) noexcept = default;
SurfaceLocator& SurfaceLocator::operator=(SurfaceLocator&&) noexcept = default;

SurfaceLocator::Hit SurfaceLocator::nearest(const Vec3& query) const {
    const Grid& g = *grid_;
    const TriangleMesh& mesh = *g.mesh;
    Hit best;
    best.distance = std::numeric_limits<double>::infinity();
    const Eigen::Vector3i home = g.cellOf(query);
    const int maxShell = g.cells.maxCoeff();
    for (int shell = 0; shell <= maxShell; ++shell) {
        // Every triangle not yet visited lies in cells at least `shell` cells away from the
        // query's cell, so at least (shell - 1) cells away from the query itself (which may lie
        // outside the grid: its cell is clamped).
        if (best.distance <= (shell - 1) * g.cell) break;
        for (int z = home.z() - shell; z <= home.z() + shell; ++z) {
            for (int y = home.y() - shell; y <= home.y() + shell; ++y) {
                for (int x = home.x() - shell; x <= home.x() + shell; ++x) {
                    const Eigen::Vector3i c(x, y, z);
                    if ((c - home).cwiseAbs().maxCoeff() != shell) continue;  // the shell only
                    if ((c.array() < 0).any() || (c.array() >= g.cells.array()).any()) continue;
                    const std::size_t i = g.index(c);
                    for (std::size_t k = g.start[i]; k < g.start[i + 1]; ++k) {
                        const std::uint32_t t = g.items[k];
                        const Vec3 a = corner(mesh, t, 0), b = corner(mesh, t, 1),
                                   cc = corner(mesh, t, 2);
                        const Vec3 bary = closestBarycentric(query, a, b, cc);
                        const Vec3 point = bary[0] * a + bary[1] * b + bary[2] * cc;
                        const double distance = (point - query).norm();
                        if (distance < best.distance ||
                            (distance == best.distance && t < best.triangle)) {
                            best = {t, bary, point, distance};
                        }
                    }
                }
            }
        }
    }
    return best;
}

// ---------------------------------------------------------------------------------------------

Result<PaintedMap> transferPaintedMap(const PaintedMap& map, const TriangleMesh& from,
                                      const TriangleMesh& to, int width, int height) {
    constexpr int kMaxSide = 16384;
    if (!from.hasUvs())
        return makeError(ErrorKind::invalidArgument,
                         from.source + ": cannot move a map from a mesh without UVs");
    if (!to.hasUvs())
        return makeError(ErrorKind::invalidArgument,
                         to.source + ": cannot move a map onto a mesh without UVs");
    if (from.triangles.empty() || to.triangles.empty()) {
        return makeError(ErrorKind::invalidArgument,
                         "cannot move a map between meshes without triangles");
    }
    if (map.width <= 0 || map.height <= 0 ||
        map.values.size() != static_cast<std::size_t>(map.width) * map.height) {
        return makeError(ErrorKind::invalidArgument, "cannot move an empty or malformed map");
    }
    if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide) {
        return makeError(ErrorKind::limit, "map size " + std::to_string(width) + " x " +
                                               std::to_string(height) + " is outside 1.." +
                                               std::to_string(kMaxSide));
    }
    const bool identical = sameSurface(from, to);
    std::unique_ptr<SurfaceLocator> locator;
    if (!identical) locator = std::make_unique<SurfaceLocator>(from);

    // Rasterise `to`: for every texel, the nearest triangle within one texel.
    const std::size_t texels = static_cast<std::size_t>(width) * height;
    std::vector<double> distance(texels, std::numeric_limits<double>::infinity());
    std::vector<std::uint32_t> triangleOf(texels, 0);
    std::vector<Vec3> baryOf(texels, Vec3::Zero());
    for (std::uint32_t t = 0; t < to.triangleCount(); ++t) {
        forTexelsNear(to, t, width, height, [&](std::size_t i, const Vec3& bary, double d) {
            if (d < distance[i]) {
                distance[i] = d;
                triangleOf[i] = t;
                baryOf[i] = bary;
            }
        });
    }

    PaintedMap out;
    out.width = width;
    out.height = height;
    out.values.assign(texels, 0.0f);
    std::vector<bool> known(texels, false);
    std::deque<std::size_t> frontier;
    for (std::size_t i = 0; i < texels; ++i) {
        if (!std::isfinite(distance[i])) continue;
        const std::uint32_t t = triangleOf[i];
        Eigen::Vector2d uv;
        if (identical) {
            uv = interpolatedUv(from, t, baryOf[i]);
        } else {
            const Vec3 point = baryOf[i][0] * corner(to, t, 0) + baryOf[i][1] * corner(to, t, 1) +
                               baryOf[i][2] * corner(to, t, 2);
            const SurfaceLocator::Hit hit = locator->nearest(point);
            uv = interpolatedUv(from, hit.triangle, hit.barycentric);
        }
        out.values[i] = static_cast<float>(map.sample(uv.x(), uv.y()));
        known[i] = true;
        frontier.push_back(i);
    }
    if (frontier.empty())
        return makeError(ErrorKind::invalidArgument,
                         to.source + ": no texel of the map is on the surface");
    // Dilation into the gutters: breadth-first from the reached texels.
    while (!frontier.empty()) {
        const std::size_t i = frontier.front();
        frontier.pop_front();
        const int x = static_cast<int>(i % width), y = static_cast<int>(i / width);
        const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4; ++k) {
            const int nx = x + dx[k], ny = y + dy[k];
            if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
            const std::size_t n = static_cast<std::size_t>(ny) * width + nx;
            if (known[n]) continue;
            known[n] = true;
            out.values[n] = out.values[i];
            frontier.push_back(n);
        }
    }
    return out;
}

Status paintTriangles(PaintedMap& map, const TriangleMesh& mesh,
                      const std::vector<std::uint32_t>& triangles, float value) {
    if (!mesh.hasUvs())
        return makeError(ErrorKind::invalidArgument,
                         mesh.source + ": cannot paint a mesh without UVs");
    if (map.width <= 0 || map.height <= 0 ||
        map.values.size() != static_cast<std::size_t>(map.width) * map.height)
        return makeError(ErrorKind::invalidArgument, "cannot paint an empty or malformed map");
    for (std::uint32_t t : triangles) {
        if (t >= mesh.triangleCount())
            return makeError(ErrorKind::invalidArgument,
                             mesh.source + ": no triangle " + std::to_string(t));
        forTexelsNear(mesh, t, map.width, map.height,
                      [&](std::size_t i, const Vec3&, double) { map.values[i] = value; });
    }
    return Ok{};
}

}  // namespace plimsoll
