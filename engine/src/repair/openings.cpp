// Basins of a closed solid (openings.h): a voxel grid of the solid's walls, then Priority-Flood
// from the grid's border. Every cell gets the lowest height water must rise to on its way out
// (the highest cell on its best path); cells below that height hold water.
#include "plimsoll/repair/openings.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>

namespace plimsoll {

namespace {

struct Grid {
    Eigen::Vector3d origin;  // corner of cell (0, 0, 0)
    double cell = 0;
    int nx = 0, ny = 0, nz = 0;
    std::size_t index(int i, int j, int k) const {
        return (static_cast<std::size_t>(k) * ny + j) * nx + i;
    }
    Eigen::Vector3d center(int i, int j, int k) const {
        return origin + cell * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
    }
    std::size_t size() const { return static_cast<std::size_t>(nx) * ny * nz; }
    /// visit(inside the grid, neighbour's index, neighbour's layer) for the six faces' neighbours
    /// of cell c = (i, j, k).
    template <class Visit>
    void forEachNeighbour(std::size_t c, int i, int j, int k, Visit&& visit) const {
        const std::size_t sy = nx, sz = static_cast<std::size_t>(nx) * ny;
        visit(i > 0, c - 1, j);
        visit(i < nx - 1, c + 1, j);
        visit(j > 0, c - sy, j - 1);
        visit(j < ny - 1, c + sy, j + 1);
        visit(k > 0, c - sz, j);
        visit(k < nz - 1, c + sz, j);
    }
};

/// Cells whose centre is inside the solid: along each vertical column, the crossings of the
/// surface in height order, entering through faces that look down and leaving through faces
/// that look up. The columns sit a small irrational share of a cell off the centres, so that
/// meshes built on the grid's own lattice hit no edge exactly.
void markInside(const TriangleMesh& mesh, const Grid& g, std::vector<std::uint8_t>& wall) {
    const double offsetX = 0.5 + 1.3e-4 * std::sqrt(2.0), offsetZ = 0.5 + 1.7e-4 * std::sqrt(3.0);
    std::vector<std::vector<std::uint32_t>> columns(static_cast<std::size_t>(g.nx) * g.nz);
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        double x0 = 1e300, x1 = -1e300, z0 = 1e300, z1 = -1e300;
        for (std::uint32_t v : tri) {
            x0 = std::min(x0, mesh.positions[v].x());
            x1 = std::max(x1, mesh.positions[v].x());
            z0 = std::min(z0, mesh.positions[v].z());
            z1 = std::max(z1, mesh.positions[v].z());
        }
        const int i0 =
            std::max(0, static_cast<int>(std::floor((x0 - g.origin.x()) / g.cell - offsetX)));
        const int i1 =
            std::min(g.nx - 1, static_cast<int>(std::ceil((x1 - g.origin.x()) / g.cell - offsetX)));
        const int k0 =
            std::max(0, static_cast<int>(std::floor((z0 - g.origin.z()) / g.cell - offsetZ)));
        const int k1 =
            std::min(g.nz - 1, static_cast<int>(std::ceil((z1 - g.origin.z()) / g.cell - offsetZ)));
        for (int k = k0; k <= k1; ++k)
            for (int i = i0; i <= i1; ++i)
                columns[static_cast<std::size_t>(k) * g.nx + i].push_back(t);
    }
    std::vector<std::pair<double, int>> crossings;
    for (int k = 0; k < g.nz; ++k)
        for (int i = 0; i < g.nx; ++i) {
            const double x = g.origin.x() + (i + offsetX) * g.cell;
            const double z = g.origin.z() + (k + offsetZ) * g.cell;
            crossings.clear();
            for (std::uint32_t t : columns[static_cast<std::size_t>(k) * g.nx + i]) {
                const Eigen::Vector3d& a = mesh.positions[mesh.triangles[t][0]];
                const Eigen::Vector3d& b = mesh.positions[mesh.triangles[t][1]];
                const Eigen::Vector3d& c = mesh.positions[mesh.triangles[t][2]];
                // Signed areas in the xz plane (seen from above): the column passes through the
                // triangle when all three agree in sign.
                const auto edge = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
                    return (q.z() - p.z()) * (x - p.x()) - (q.x() - p.x()) * (z - p.z());
                };
                const double wa = edge(b, c), wb = edge(c, a), wc = edge(a, b);
                const double sum = wa + wb + wc;
                if (sum == 0) continue;  // a vertical face
                if (!((wa >= 0 && wb >= 0 && wc >= 0) || (wa <= 0 && wb <= 0 && wc <= 0))) continue;
                const double y = (wa * a.y() + wb * b.y() + wc * c.y()) / sum;
                const double normalY = (b - a).cross(c - a).y();
                crossings.emplace_back(y, normalY < 0 ? 1 : -1);
            }
            std::sort(crossings.begin(), crossings.end());
            int winding = 0;
            std::size_t next = 0;
            for (int j = 0; j < g.ny; ++j) {
                const double y = g.origin.y() + (j + 0.5) * g.cell;
                while (next < crossings.size() && crossings[next].first <= y)
                    winding += crossings[next++].second;
                if (winding > 0) wall[g.index(i, j, k)] = 1;
            }
        }
}

/// Cells the surface passes through: points spread over every triangle closer than half a cell.
void markSurface(const TriangleMesh& mesh, const Grid& g, std::vector<std::uint8_t>& wall) {
    const auto mark = [&](const Eigen::Vector3d& p) {
        const Eigen::Vector3d q = (p - g.origin) / g.cell;
        const int i = std::clamp(static_cast<int>(std::floor(q.x())), 0, g.nx - 1);
        const int j = std::clamp(static_cast<int>(std::floor(q.y())), 0, g.ny - 1);
        const int k = std::clamp(static_cast<int>(std::floor(q.z())), 0, g.nz - 1);
        wall[g.index(i, j, k)] = 1;
    };
    for (const Triangle& t : mesh.triangles) {
        const Eigen::Vector3d& a = mesh.positions[t[0]];
        const Eigen::Vector3d& b = mesh.positions[t[1]];
        const Eigen::Vector3d& c = mesh.positions[t[2]];
        // Measured in cells, where every length is bounded by the grid's size: a length in
        // metres of coordinates near 1e160 squares past the largest double.
        const Eigen::Vector3d ga = (a - g.origin) / g.cell, gb = (b - g.origin) / g.cell,
                              gc = (c - g.origin) / g.cell;
        const double longest = std::max({(gb - ga).norm(), (gc - gb).norm(), (ga - gc).norm()});
        const int steps = std::max(1, static_cast<int>(std::ceil(2 * longest)));
        for (int s = 0; s <= steps; ++s)
            for (int r = 0; r + s <= steps; ++r)
                mark(a + (b - a) * (double(s) / steps) + (c - a) * (double(r) / steps));
    }
}

}  // namespace

std::vector<Basin> findBasins(const TriangleMesh& solid, double solidVolume,
                              const BasinSettings& settings) {
    std::vector<Basin> basins;
    if (solid.triangles.empty() || !(solidVolume > 0)) return basins;
    const Bounds3 bounds = computeBounds(solid);
    const Eigen::Vector3d extent = bounds.max - bounds.min;
    // Beyond 1e300 the grid's own border (two cells beyond the bounds) is no longer a double.
    if (!extent.allFinite() || !(extent.maxCoeff() > 0) || !(extent.maxCoeff() < 1e300))
        return basins;
    Grid g;
    // Two cells of border all round, so that the outside surrounds the solid.
    g.cell = extent.maxCoeff() / std::max(settings.resolution, 8);
    const auto cellsFor = [&](double cell) { return ((extent.array() / cell).ceil() + 4).prod(); };
    while (cellsFor(g.cell) > static_cast<double>(settings.maxCells)) g.cell *= 1.1;
    g.origin = bounds.min - Eigen::Vector3d::Constant(2 * g.cell);
    g.nx = static_cast<int>(std::ceil(extent.x() / g.cell)) + 4;
    g.ny = static_cast<int>(std::ceil(extent.y() / g.cell)) + 4;
    g.nz = static_cast<int>(std::ceil(extent.z() / g.cell)) + 4;

    std::vector<std::uint8_t> wall(g.size(), 0);
    markInside(solid, g, wall);
    markSurface(solid, g, wall);

    // Priority-Flood: the level of a cell is the lowest "highest cell" over the paths from it
    // to the border; the border cells start at their own height. Levels are integer layers, so
    // the queue is one bucket per layer.
    constexpr int unreached = std::numeric_limits<int>::max();
    std::vector<int> level(g.size(), unreached);
    std::vector<std::vector<std::size_t>> buckets(g.ny);
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                if (i != 0 && j != 0 && k != 0 && i != g.nx - 1 && j != g.ny - 1 && k != g.nz - 1)
                    continue;
                const std::size_t c = g.index(i, j, k);
                if (wall[c]) continue;
                level[c] = j;
                buckets[j].push_back(c);
            }
    const std::size_t sz = static_cast<std::size_t>(g.nx) * g.ny;
    const auto coords = [&](std::size_t c, int& i, int& j, int& k) {
        i = static_cast<int>(c % g.nx);
        j = static_cast<int>((c / g.nx) % g.ny);
        k = static_cast<int>(c / sz);
    };
    for (int l = 0; l < g.ny; ++l) {
        for (std::size_t n = 0; n < buckets[l].size(); ++n) {
            const std::size_t c = buckets[l][n];
            if (level[c] != l) continue;
            int i, j, k;
            coords(c, i, j, k);
            const auto visit = [&](bool inside, std::size_t d, int dj) {
                if (!inside || wall[d]) return;
                const int lv = std::max(l, dj);
                if (lv < level[d]) {
                    level[d] = lv;
                    buckets[lv].push_back(d);
                }
            };
            g.forEachNeighbour(c, i, j, k, visit);
        }
        buckets[l].clear();
        buckets[l].shrink_to_fit();
    }

    // The water: reached cells below their level, in connected lakes.
    std::vector<int> lake(g.size(), -1);
    std::vector<std::size_t> stack;
    const double cellVolume = g.cell * g.cell * g.cell;
    for (std::size_t start = 0; start < g.size(); ++start) {
        int i, j, k;
        coords(start, i, j, k);
        if (wall[start] || level[start] == unreached || level[start] <= j || lake[start] >= 0)
            continue;
        Basin basin;
        const int id = static_cast<int>(basins.size()) + 1000000;  // not kept unless it counts
        std::size_t count = 0;
        int lowest = unreached, spill = level[start];
        Eigen::Vector3i lo(i, j, k), hi(i, j, k);
        std::size_t seed = start;
        int seedScore = -1;
        stack.assign(1, start);
        lake[start] = id;
        while (!stack.empty()) {
            const std::size_t c = stack.back();
            stack.pop_back();
            int ci, cj, ck;
            coords(c, ci, cj, ck);
            ++count;
            spill = std::min(spill, level[c]);
            lowest = std::min(lowest, cj);
            lo = lo.cwiseMin(Eigen::Vector3i(ci, cj, ck));
            hi = hi.cwiseMax(Eigen::Vector3i(ci, cj, ck));
            // The seed: a cell with water on all six sides, as low as possible.
            int open = 0;
            const auto push = [&](bool inside, std::size_t d, int dj) {
                if (!inside || wall[d] || level[d] == unreached || level[d] <= dj) return;
                ++open;
                if (lake[d] < 0) {
                    lake[d] = id;
                    stack.push_back(d);
                }
            };
            g.forEachNeighbour(c, ci, cj, ck, push);
            const int score = open * 100000 - cj;
            if (score > seedScore) {
                seedScore = score;
                seed = c;
            }
        }
        basin.cellSize = g.cell;
        basin.volume = static_cast<double>(count) * cellVolume;
        basin.spillHeight = g.origin.y() + spill * g.cell;
        int si, sj, sk;
        coords(seed, si, sj, sk);
        basin.seed = g.center(si, sj, sk);
        basin.boundsMin = g.origin + g.cell * lo.cast<double>();
        basin.boundsMax = g.origin + g.cell * (hi.cast<double>() + Eigen::Vector3d::Ones());
        if (basin.volume < settings.minVolumeShare * solidVolume) continue;
        if (spill - lowest < settings.minDepthCells) continue;
        if (sj > spill - 2) continue;
        basins.push_back(basin);
    }
    // Largest first; equal volumes (a symmetric pair of holds) by the seed's place, so that the
    // order, which a project's per-cap settings are indexed by, depends on the mesh alone.
    std::sort(basins.begin(), basins.end(), [](const Basin& a, const Basin& b) {
        if (a.volume != b.volume) return a.volume > b.volume;
        return std::tuple(a.seed.x(), a.seed.z(), a.seed.y()) <
               std::tuple(b.seed.x(), b.seed.z(), b.seed.y());
    });
    return basins;
}

}  // namespace plimsoll
