// Mesh validation (validate.h). Checks run in dependency order: emptiness, UV presence and
// finiteness first, because every later check needs finite coordinates; then per-triangle
// areas, topology after welding by position, and the UV map (range, exact overlap, mirroring).
//
// Precondition: every triangle index is below vertexCount() (loadMesh and the generators
// guarantee it).
#include "plimsoll/geometry/validate.h"

#include "plimsoll/geometry/uv_layout.h"

#include "core/printed.h"
#include "geometry/uv_clip.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <optional>
#include <span>

namespace plimsoll {

namespace {

using uvclip::intersectionArea;
using uvclip::Point2;
using uvclip::UvTriangle;

// Zero 3D area, relative to the squared bounding-box diagonal: scale-free, and far above the
// rounding of the cross product for any triangle that is not a sliver.
constexpr double kDegenerateArea = 1e-12;
// Zero UV area, relative to the UV bounding-box area.
constexpr double kDegenerateUvArea = 1e-14;
// Per pair of triangles, overlaps below this share of the total UV area are clipping rounding
// (neighbours sharing an edge), not overlap.
constexpr double kOverlapRounding = 1e-12;
// Overlap below this share of the total UV area is a warning, not an error: about a texel of a
// 1024 x 1024 texture, typically a sliver folded over its neighbours (spot.obj has one) that
// cannot shift a texel's centroid measurably.
constexpr double kNegligibleOverlap = 1e-6;
// The overlap search stops after clipping this many pairs per triangle (plus a fixed allowance):
// real maps clip about 7 (their neighbours), but a map with every face on the same UV square
// would cost n^2 / 2.
constexpr std::size_t kPairsPerTriangle = 64;
constexpr std::size_t kPairAllowance = 1'000'000;

void add(ValidationReport& report, ProblemKind kind, Severity severity, std::size_t count,
         double surfaceFraction, std::string message) {
    report.problems.push_back({kind, severity, count, surfaceFraction, std::move(message)});
}

// ---------------------------------------------------------------------------------------------
// Per-triangle facts shared by the checks.

struct TriangleFacts {
    std::vector<double> area;      // 3D area (m^2)
    std::vector<bool> degenerate;  // zero 3D area or a repeated index
    double totalArea = 0;
};

TriangleFacts triangleFacts(const TriangleMesh& mesh) {
    const double diagonal = computeBounds(mesh).diagonal();
    const double threshold = kDegenerateArea * diagonal * diagonal;
    TriangleFacts facts;
    facts.area.reserve(mesh.triangleCount());
    facts.degenerate.reserve(mesh.triangleCount());
    for (const Triangle& t : mesh.triangles) {
        const double area = triangleAreaVector(mesh, t).norm();
        const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
        facts.area.push_back(area);
        facts.degenerate.push_back(repeated || area <= threshold);
        facts.totalArea += area;
    }
    return facts;
}

std::size_t countMarked(const std::vector<bool>& marked) {
    return static_cast<std::size_t>(std::count(marked.begin(), marked.end(), true));
}

// Share of the 3D surface covered by the marked triangles.
double areaShare(const std::vector<bool>& marked, const TriangleFacts& facts) {
    if (facts.totalArea <= 0) return 0;
    double area = 0;
    for (std::size_t t = 0; t < marked.size(); ++t) {
        if (marked[t]) area += facts.area[t];
    }
    return area / facts.totalArea;
}

// ---------------------------------------------------------------------------------------------
// Finiteness: NaN or Inf makes every geometric check meaningless, so it ends validation.

// Every check below indexes the vertex arrays with the triangles' indices: a mesh built in
// memory (not by the importer, which guarantees them) may name vertices it does not have.
bool checkIndices(const TriangleMesh& mesh, ValidationReport& report) {
    std::size_t bad = 0;
    for (const Triangle& t : mesh.triangles) {
        if (t[0] >= mesh.vertexCount() || t[1] >= mesh.vertexCount() || t[2] >= mesh.vertexCount())
            ++bad;
    }
    if (bad == 0) return true;
    add(report, ProblemKind::IndexOutOfRange, Severity::Error, bad, 0,
        printed("%zu triangles name vertices past the last of the %zu vertices; other checks "
                "skipped",
                bad, mesh.vertexCount()));
    return false;
}

bool checkFinite(const TriangleMesh& mesh, ValidationReport& report) {
    std::vector<bool> bad(mesh.vertexCount(), false);
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        const bool badUv = v < mesh.uvs.size() && !mesh.uvs[v].allFinite();
        bad[v] = badUv || !mesh.positions[v].allFinite();
    }
    const std::size_t badVertices = countMarked(bad);
    if (badVertices == 0) return true;
    std::size_t badTriangles = 0;
    for (const Triangle& t : mesh.triangles) {
        if (bad[t[0]] || bad[t[1]] || bad[t[2]]) ++badTriangles;
    }
    add(report, ProblemKind::NonFinite, Severity::Error, badTriangles, 0,
        printed("%zu vertices (used by %zu triangles) have NaN or Inf coordinates; "
                "geometric checks skipped",
                badVertices, badTriangles));
    return false;
}

void checkUvsPresent(const TriangleMesh& mesh, ValidationReport& report) {
    if (mesh.hasUvs()) return;
    add(report, ProblemKind::MissingUvs, Severity::Error, mesh.triangleCount(), 1,
        mesh.uvs.empty()
            ? std::string("no texture coordinates: the mesh cannot be baked with its own UVs")
            : printed("%zu texture coordinates for %zu vertices: the UVs are unusable",
                      mesh.uvs.size(), mesh.vertexCount()));
}

// ---------------------------------------------------------------------------------------------
// Zero-area triangles.

void checkDegenerate(const TriangleFacts& facts, ValidationReport& report) {
    const std::size_t count = countMarked(facts.degenerate);
    if (count == 0) return;
    add(report, ProblemKind::DegenerateTriangle, Severity::Warning, count,
        areaShare(facts.degenerate, facts),
        printed("%zu triangles have zero area (repeated or collinear vertices): "
                "they contribute nothing",
                count));
}

double uvBoxArea(const TriangleMesh& mesh) {
    Eigen::AlignedBox2d box;
    for (const Eigen::Vector2d& uv : mesh.uvs) box.extend(uv);
    return box.isEmpty() ? 0.0 : box.volume();
}

void checkDegenerateUv(const TriangleMesh& mesh, const TriangleFacts& facts,
                       ValidationReport& report) {
    const double threshold = kDegenerateUvArea * uvBoxArea(mesh);
    std::vector<bool> lost(mesh.triangleCount(), false);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        lost[t] =
            !facts.degenerate[t] && std::abs(triangleUvArea(mesh, mesh.triangles[t])) <= threshold;
    }
    const std::size_t count = countMarked(lost);
    if (count == 0) return;
    add(report, ProblemKind::DegenerateUvTriangle, Severity::Error, count, areaShare(lost, facts),
        printed("%zu triangles have zero UV area but nonzero 3D area: "
                "their area is lost in the bake",
                count));
}

// ---------------------------------------------------------------------------------------------
// Edges: one record per (triangle, edge), sorted so that uses of the same undirected edge are
// adjacent.

struct EdgeUse {
    std::uint64_t key;  // (smaller vertex id << 32) | larger vertex id
    std::uint32_t triangle;
    bool forward;  // walked from the smaller id to the larger one
};

// Edge uses of the triangles under the vertex ids `id` (a welding). Triangles with a repeated
// id have zero area and would only pair their own edges with each other: they are left out.
std::vector<EdgeUse> sortedEdgeUses(const TriangleMesh& mesh,
                                    const std::vector<std::uint32_t>& id) {
    std::vector<EdgeUse> uses;
    uses.reserve(3 * mesh.triangleCount());
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        const std::array<std::uint32_t, 3> v{id[mesh.triangles[t][0]], id[mesh.triangles[t][1]],
                                             id[mesh.triangles[t][2]]};
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t from = v[k], to = v[(k + 1) % 3];
            const std::uint64_t lo = std::min(from, to), hi = std::max(from, to);
            uses.push_back({(lo << 32) | hi, t, from < to});
        }
    }
    std::sort(uses.begin(), uses.end(), [](const EdgeUse& a, const EdgeUse& b) {
        return a.key != b.key ? a.key < b.key : a.triangle < b.triangle;
    });
    return uses;
}

// Calls visit(span of uses) once per undirected edge.
template <class Visit>
void forEachEdge(const std::vector<EdgeUse>& uses, Visit visit) {
    for (std::size_t begin = 0; begin < uses.size();) {
        std::size_t end = begin + 1;
        while (end < uses.size() && uses[end].key == uses[begin].key) ++end;
        visit(std::span<const EdgeUse>(uses.data() + begin, end - begin));
        begin = end;
    }
}

// ---------------------------------------------------------------------------------------------
// Topology after welding by position (UV seams split vertices but not the surface).

// Divergence theorem: V = sum dot(v0, v1 x v2) / 6, taken about the bounding-box centre so that
// a mesh far from the origin does not lose digits to cancellation.
double signedVolume(const TriangleMesh& mesh) {
    const Eigen::Vector3d centre = computeBounds(mesh).center();
    double volume = 0;
    for (const Triangle& t : mesh.triangles) {
        const Eigen::Vector3d a = mesh.positions[t[0]] - centre;
        const Eigen::Vector3d b = mesh.positions[t[1]] - centre;
        const Eigen::Vector3d c = mesh.positions[t[2]] - centre;
        volume += a.dot(b.cross(c));
    }
    return volume / 6;
}

struct EdgeDefects {
    std::size_t count = 0;
    std::vector<bool> triangles;  // triangles along the defective edges
    explicit EdgeDefects(std::size_t triangleCount) : triangles(triangleCount, false) {}
    void mark(std::span<const EdgeUse> edge) {
        ++count;
        for (const EdgeUse& use : edge) triangles[use.triangle] = true;
    }
};

void checkTopology(const TriangleMesh& mesh, const TriangleFacts& facts, ValidationReport& report) {
    EdgeDefects open(mesh.triangleCount()), nonManifold(mesh.triangleCount()),
        inconsistent(mesh.triangleCount());
    forEachEdge(sortedEdgeUses(mesh, weldByPosition(mesh)), [&](std::span<const EdgeUse> edge) {
        if (edge.size() == 1) {
            open.mark(edge);
        } else if (edge.size() > 2) {
            nonManifold.mark(edge);
        } else if (edge[0].forward == edge[1].forward) {
            inconsistent.mark(edge);
        }
    });
    if (open.count > 0) {
        add(report, ProblemKind::OpenSurface, Severity::Error, open.count,
            areaShare(open.triangles, facts),
            printed("%zu boundary edges: the surface is not closed", open.count));
    }
    if (nonManifold.count > 0) {
        add(report, ProblemKind::NonManifoldEdge, Severity::Error, nonManifold.count,
            areaShare(nonManifold.triangles, facts),
            printed("%zu edges are shared by more than two triangles", nonManifold.count));
    }
    if (inconsistent.count > 0) {
        add(report, ProblemKind::InconsistentOrientation, Severity::Error, inconsistent.count,
            areaShare(inconsistent.triangles, facts),
            printed("%zu edges are used twice in the same direction: neighbouring triangles "
                    "have opposite winding",
                    inconsistent.count));
    }
    if (open.count + nonManifold.count + inconsistent.count > 0) return;
    // Only a closed, consistently wound surface has a well-defined sign of volume.
    const double volume = signedVolume(mesh);
    if (volume < 0) {
        add(report, ProblemKind::InwardNormals, Severity::Error, mesh.triangleCount(), 1,
            printed("signed volume %.6g is negative: the triangles are wound clockwise seen "
                    "from outside (normals point inwards)",
                    volume));
    }
}

// ---------------------------------------------------------------------------------------------
// UV range.

void checkUvRange(const TriangleMesh& mesh, const TriangleFacts& facts, ValidationReport& report) {
    const auto outside = [](const Eigen::Vector2d& uv) {
        return (uv.array() < 0.0).any() || (uv.array() > 1.0).any();
    };
    std::vector<bool> marked(mesh.triangleCount(), false);
    Eigen::AlignedBox2d box;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        for (std::uint32_t v : mesh.triangles[t]) {
            marked[t] = marked[t] || outside(mesh.uvs[v]);
            box.extend(mesh.uvs[v]);
        }
    }
    const std::size_t count = countMarked(marked);
    if (count == 0) return;
    add(report, ProblemKind::UvOutOfRange, Severity::Warning, count, areaShare(marked, facts),
        printed("%zu triangles have UVs outside [0,1] (u %.4g..%.4g, v %.4g..%.4g): they will "
                "be remapped into the texture",
                count, box.min().x(), box.max().x(), box.min().y(), box.max().y()));
}

// ---------------------------------------------------------------------------------------------
// Exact UV overlap: a uniform grid finds candidate pairs, and each pair's intersection area comes
// from clipping one triangle against the other (Sutherland-Hodgman; both are convex).

// floor(x) clamped to 0..last, in floating point before the conversion: UVs near the double
// range overflow differences and sums to Inf (and Inf / Inf to NaN), and converting either to
// an integer is undefined behaviour.
int clampedCell(double x, int last) {
    if (!(x > 0)) return 0;  // NaN too
    if (x >= last) return last;
    return static_cast<int>(x);
}

// Uniform grid over the UV bounding box; each cell lists the triangles whose box touches it
// (compressed rows: cell c holds items[start[c] .. start[c + 1])).
class UvGrid {
public:
    explicit UvGrid(const std::vector<UvTriangle>& triangles) {
        Eigen::AlignedBox2d bounds;
        double extentSum = 0;
        for (const UvTriangle& t : triangles) {
            bounds.extend(t.box);
            extentSum += t.box.sizes().maxCoeff();
        }
        origin_ = bounds.min();
        const Point2 size = bounds.sizes();
        // Cells of the mean triangle extent keep per-cell lists short (larger cells visit more
        // pairs on maps with uneven triangle sizes); the cell count is capped near the triangle
        // count so that sparse or long thin maps do not allocate huge grids.
        const double n = static_cast<double>(triangles.size());
        cell_ = std::max(extentSum / n, std::sqrt(size.prod() / (4.0 * n)));
        cell_ = std::max(cell_, size.maxCoeff() / 4096.0);
        nx_ = std::max(1, clampedCell(std::ceil(size.x() / cell_), 4096));
        ny_ = std::max(1, clampedCell(std::ceil(size.y() / cell_), 4096));
        fill(triangles);
    }

    int cellCount() const { return nx_ * ny_; }
    std::span<const std::uint32_t> cell(int c) const {
        return {items_.data() + start_[static_cast<std::size_t>(c)],
                start_[static_cast<std::size_t>(c) + 1] - start_[static_cast<std::size_t>(c)]};
    }
    // The cell holding point p (clamped to the grid).
    int cellOf(const Point2& p) const { return column(p.x()) + nx_ * row(p.y()); }

private:
    int column(double u) const { return clampedCell((u - origin_.x()) / cell_, nx_ - 1); }
    int row(double v) const { return clampedCell((v - origin_.y()) / cell_, ny_ - 1); }

    template <class Visit>
    void forCellsOf(const Eigen::AlignedBox2d& box, Visit visit) const {
        for (int y = row(box.min().y()); y <= row(box.max().y()); ++y) {
            for (int x = column(box.min().x()); x <= column(box.max().x()); ++x) {
                visit(static_cast<std::size_t>(x + nx_ * y));
            }
        }
    }

    void fill(const std::vector<UvTriangle>& triangles) {
        start_.assign(static_cast<std::size_t>(cellCount()) + 1, 0);
        for (const UvTriangle& t : triangles) {
            forCellsOf(t.box, [&](std::size_t c) { ++start_[c + 1]; });
        }
        std::partial_sum(start_.begin(), start_.end(), start_.begin());
        items_.resize(start_.back());
        std::vector<std::size_t> cursor(start_.begin(), start_.end() - 1);
        for (std::uint32_t i = 0; i < triangles.size(); ++i) {
            forCellsOf(triangles[i].box, [&](std::size_t c) { items_[cursor[c]++] = i; });
        }
    }

    Point2 origin_;
    double cell_ = 1;
    int nx_ = 1, ny_ = 1;
    std::vector<std::size_t> start_;
    std::vector<std::uint32_t> items_;
};

struct OverlapResult {
    double area = 0;                // summed pairwise intersection area (UV units)
    std::vector<bool> overlapping;  // per mesh triangle
    bool truncated = false;         // pair budget exhausted: area is a lower bound
    std::size_t pairsClipped = 0;
};

OverlapResult findUvOverlap(const std::vector<UvTriangle>& uv,
                            const std::vector<std::uint32_t>& meshIndex, double totalUvArea,
                            std::size_t meshTriangles) {
    OverlapResult result;
    result.overlapping.assign(meshTriangles, false);
    if (uv.size() < 2) return result;
    const UvGrid grid(uv);
    const double rounding = kOverlapRounding * totalUvArea;
    const std::size_t budget = kPairsPerTriangle * uv.size() + kPairAllowance;
    for (int c = 0; c < grid.cellCount(); ++c) {
        const std::span<const std::uint32_t> members = grid.cell(c);
        for (std::size_t i = 0; i < members.size(); ++i) {
            for (std::size_t j = i + 1; j < members.size(); ++j) {
                const UvTriangle& a = uv[members[i]];
                const UvTriangle& b = uv[members[j]];
                if (!a.box.intersects(b.box)) continue;
                // A pair sharing several cells is handled once: in the cell holding the lower
                // corner of the intersection of their boxes.
                if (grid.cellOf(a.box.intersection(b.box).min()) != c) continue;
                if (result.pairsClipped == budget) {
                    result.truncated = true;
                    return result;
                }
                ++result.pairsClipped;
                const double area = intersectionArea(a, b);
                if (area <= rounding) continue;
                result.area += area;
                result.overlapping[meshIndex[members[i]]] = true;
                result.overlapping[meshIndex[members[j]]] = true;
            }
        }
    }
    return result;
}

// Triangles whose UV orientation is opposite to the one holding the majority of the UV area
// (on a tie, the clockwise ones).
std::vector<bool> mirroredTriangles(const TriangleMesh& mesh) {
    double total = 0;
    for (const Triangle& t : mesh.triangles) total += triangleUvArea(mesh, t);
    std::vector<bool> mirrored(mesh.triangleCount(), false);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const double area = triangleUvArea(mesh, mesh.triangles[t]);
        mirrored[t] = total > 0 ? area < 0 : (total < 0 ? area > 0 : area < 0);
    }
    return mirrored;
}

void checkUvOverlap(const TriangleMesh& mesh, const TriangleFacts& facts,
                    ValidationReport& report) {
    const double threshold = kDegenerateUvArea * uvBoxArea(mesh);
    std::vector<UvTriangle> uv;
    std::vector<std::uint32_t> meshIndex;
    double totalUvArea = 0;
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const double area = triangleUvArea(mesh, tri);
        totalUvArea += std::abs(area);
        if (std::abs(area) <= threshold) continue;  // zero UV area overlaps nothing
        UvTriangle u;
        u.corners = {mesh.uvs[tri[0]], mesh.uvs[tri[1]], mesh.uvs[tri[2]]};
        if (area < 0) std::swap(u.corners[1], u.corners[2]);
        for (const Point2& p : u.corners) u.box.extend(p);
        uv.push_back(u);
        meshIndex.push_back(t);
    }
    const OverlapResult overlap = findUvOverlap(uv, meshIndex, totalUvArea, mesh.triangleCount());
    const std::size_t count = countMarked(overlap.overlapping);
    if (count == 0) return;
    const double fraction = overlap.area / totalUvArea;
    const bool negligible = fraction < kNegligibleOverlap && !overlap.truncated;
    std::string message =
        printed("%zu triangles overlap in UV: the overlapping area is %.3g%% of the total UV area",
                count, 100.0 * fraction);
    if (overlap.truncated) {
        message += printed(" (at least: the search stopped after %zu overlapping candidate pairs)",
                           overlap.pairsClipped);
    }
    // Mirrored triangles overlapping others: the usual cause (two halves of a model sharing
    // one half of the texture), which a texel sum would silently count twice.
    std::vector<bool> mirroredOverlap = overlap.overlapping;
    const std::vector<bool> mirrored = mirroredTriangles(mesh);
    for (std::size_t t = 0; t < mirroredOverlap.size(); ++t) {
        mirroredOverlap[t] = mirroredOverlap[t] && mirrored[t];
    }
    message += printed(" (%.3g%% of the surface; %.3g%% of the surface is mirrored onto other UVs)",
                       100.0 * areaShare(overlap.overlapping, facts),
                       100.0 * areaShare(mirroredOverlap, facts));
    message += negligible ? "; negligible for baking (under a millionth of the UV area)"
                          : "; the map is not bijective";
    add(report, ProblemKind::UvOverlap, negligible ? Severity::Warning : Severity::Error, count,
        areaShare(overlap.overlapping, facts), std::move(message));
}

// ---------------------------------------------------------------------------------------------
// UV tiles: a map spread over several unit squares (UDIM tiles, or a texture repeated along a
// long part), so wider than one unit. One physics texture holds them all, each tile at a fraction
// of the resolution.

void checkUvTiles(const TriangleMesh& mesh, const TriangleFacts& facts, ValidationReport& report) {
    std::vector<std::pair<long long, long long>> tileOf(mesh.triangleCount());
    std::vector<std::pair<long long, long long>> tiles;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Eigen::Vector2d centre =
            (mesh.uvs[tri[0]] + mesh.uvs[tri[1]] + mesh.uvs[tri[2]]) / 3.0;
        // Clamped before the conversion (undefined beyond long long's range; a centre of
        // UVs near 1e308 is Inf): every tile past 1e15 is "far away", which is all that counts.
        auto tile = [](double c) {
            return static_cast<long long>(std::floor(std::clamp(c, -1e15, 1e15)));
        };
        tileOf[t] = {tile(centre.x()), tile(centre.y())};
        tiles.push_back(tileOf[t]);
    }
    std::sort(tiles.begin(), tiles.end());
    tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
    // A map merely offset across a tile border (extent under one unit) is not tiled.
    Eigen::AlignedBox2d box;
    for (const Eigen::Vector2d& uv : mesh.uvs) box.extend(uv);
    if (tiles.size() <= 1 || box.sizes().maxCoeff() <= 1.0) return;
    std::vector<bool> outsideFirst(mesh.triangleCount(), false);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
        outsideFirst[t] = tileOf[t] != std::pair<long long, long long>{0, 0};
    add(report, ProblemKind::UvMultipleTiles, Severity::Warning, tiles.size(),
        areaShare(outsideFirst, facts),
        printed("the UVs spread over %zu unit tiles (%zu triangles outside tile 0,0): they share "
                "one physics texture, each tile at a fraction of its resolution",
                tiles.size(), countMarked(outsideFirst)));
}

// ---------------------------------------------------------------------------------------------
// UV-area distortion: world area per UV area, area-weighted percentiles over the surface.

// Area-weighted quantile q of (density, weight) pairs sorted by density.
double weightedQuantile(const std::vector<std::pair<double, double>>& sorted, double total,
                        double q) {
    double running = 0;
    for (const auto& [density, weight] : sorted) {
        running += weight;
        if (running >= q * total) return density;
    }
    return sorted.back().first;
}

void checkUvDistortion(const TriangleMesh& mesh, const TriangleFacts& facts,
                       ValidationReport& report) {
    std::vector<double> density(mesh.triangleCount(), 0.0);  // 0: no UV area
    std::vector<std::pair<double, double>> sorted;
    double total = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const double uvArea = std::abs(triangleUvArea(mesh, mesh.triangles[t]));
        if (facts.degenerate[t] || uvArea <= 0) continue;
        density[t] = facts.area[t] / uvArea;
        sorted.emplace_back(density[t], facts.area[t]);
        total += facts.area[t];
    }
    if (sorted.empty()) return;
    std::sort(sorted.begin(), sorted.end());
    const double low = weightedQuantile(sorted, total, 0.01);
    const double high = weightedQuantile(sorted, total, 0.99);
    report.uvAreaSpread = low > 0 ? high / low : std::numeric_limits<double>::infinity();
    if (report.uvAreaSpread <= kMaxUvAreaSpread) return;
    // Affected: triangles more than sqrt(limit) from the median either way (so that the rest
    // spans at most the limit).
    const double median = weightedQuantile(sorted, total, 0.5);
    const double band = std::sqrt(kMaxUvAreaSpread);
    std::vector<bool> affected(mesh.triangleCount(), false);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        affected[t] = density[t] > 0 && (density[t] > band * median || density[t] * band < median);
    }
    add(report, ProblemKind::UvDistortion, Severity::Warning, countMarked(affected),
        areaShare(affected, facts),
        printed("the world area per UV area varies by a factor of %.3g over the surface (99th over "
                "1st percentile; above %.3g the coarsest texels limit the accuracy); %zu "
                "triangles lie more than %.3g times from the median",
                report.uvAreaSpread, kMaxUvAreaSpread, countMarked(affected), band));
}

// ---------------------------------------------------------------------------------------------
// Mirrored UV islands.

void checkUvMirrored(const TriangleMesh& mesh, const TriangleFacts& facts,
                     ValidationReport& report) {
    const std::vector<std::uint32_t> island = uvIslands(mesh);
    std::vector<double> islandArea(mesh.triangleCount(), 0.0);
    double total = 0;
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        const double area = triangleUvArea(mesh, mesh.triangles[t]);
        islandArea[island[t]] += area;
        total += area;
    }
    // The orientation holding the majority of the UV area is the intended one.
    const auto mirrored = [&](double area) { return area * total < 0; };
    std::size_t islandCount = 0;
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        if (island[t] == t && mirrored(islandArea[t])) ++islandCount;
    }
    if (islandCount == 0) return;
    std::vector<bool> marked(mesh.triangleCount(), false);
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        marked[t] = mirrored(islandArea[island[t]]);
    }
    const std::size_t triangles = countMarked(marked);
    add(report, ProblemKind::UvMirrored, Severity::Warning, islandCount, areaShare(marked, facts),
        printed("%zu UV islands (%zu triangles) are mirrored relative to the rest of the map",
                islandCount, triangles));
}

}  // namespace

// ---------------------------------------------------------------------------------------------

const char* problemCode(ProblemKind kind) {
    switch (kind) {
        case ProblemKind::EmptyMesh:
            return "empty-mesh";
        case ProblemKind::NonFinite:
            return "non-finite";
        case ProblemKind::MissingUvs:
            return "missing-uvs";
        case ProblemKind::DegenerateTriangle:
            return "degenerate-triangle";
        case ProblemKind::DegenerateUvTriangle:
            return "degenerate-uv-triangle";
        case ProblemKind::OpenSurface:
            return "open-surface";
        case ProblemKind::NonManifoldEdge:
            return "non-manifold-edge";
        case ProblemKind::InconsistentOrientation:
            return "inconsistent-orientation";
        case ProblemKind::InwardNormals:
            return "inward-normals";
        case ProblemKind::UvOutOfRange:
            return "uv-out-of-range";
        case ProblemKind::UvOverlap:
            return "uv-overlap";
        case ProblemKind::UvMirrored:
            return "uv-mirrored";
        case ProblemKind::UvMultipleTiles:
            return "uv-multiple-tiles";
        case ProblemKind::UvDistortion:
            return "uv-distortion";
        case ProblemKind::IndexOutOfRange:
            return "index-out-of-range";
    }
    return "unknown";
}

bool isUvProblem(ProblemKind kind) {
    switch (kind) {
        case ProblemKind::MissingUvs:
        case ProblemKind::DegenerateUvTriangle:
        case ProblemKind::UvOutOfRange:
        case ProblemKind::UvOverlap:
        case ProblemKind::UvMirrored:
        case ProblemKind::UvMultipleTiles:
        case ProblemKind::UvDistortion:
            return true;
        default:
            return false;
    }
}

bool ValidationReport::has(ProblemKind kind) const {
    return std::any_of(problems.begin(), problems.end(),
                       [kind](const Problem& p) { return p.kind == kind; });
}

bool ValidationReport::hasErrors() const {
    return std::any_of(problems.begin(), problems.end(),
                       [](const Problem& p) { return p.severity == Severity::Error; });
}

bool ValidationReport::closedSolid() const {
    return !has(ProblemKind::EmptyMesh) && !has(ProblemKind::IndexOutOfRange) &&
           !has(ProblemKind::NonFinite) && !has(ProblemKind::OpenSurface) &&
           !has(ProblemKind::NonManifoldEdge) && !has(ProblemKind::InconsistentOrientation) &&
           !has(ProblemKind::InwardNormals);
}

std::string ValidationReport::format() const {
    std::string out;
    for (Severity severity : {Severity::Error, Severity::Warning}) {
        for (const Problem& p : problems) {
            if (p.severity != severity) continue;
            out += source + ": " + (severity == Severity::Error ? "error" : "warning") + " [" +
                   problemCode(p.kind) + "]: " + p.message + "\n";
        }
    }
    return out;
}

namespace {

/// The checks of the surface itself, in validateMesh's order; the facts for the UV checks, or
/// none where the mesh is too broken for them.
std::optional<TriangleFacts> checkSurface(const TriangleMesh& mesh, ValidationReport& report) {
    report.source = mesh.source;
    if (mesh.triangles.empty()) {
        add(report, ProblemKind::EmptyMesh, Severity::Error, 0, 0, "the mesh has no triangles");
        return std::nullopt;
    }
    if (!checkIndices(mesh, report)) return std::nullopt;
    checkUvsPresent(mesh, report);
    if (!checkFinite(mesh, report)) return std::nullopt;
    TriangleFacts facts = triangleFacts(mesh);
    checkDegenerate(facts, report);
    checkTopology(mesh, facts, report);
    return facts;
}

}  // namespace

ValidationReport validateSurface(const TriangleMesh& mesh) {
    ValidationReport report;
    checkSurface(mesh, report);
    return report;
}

ValidationReport validateMesh(const TriangleMesh& mesh) {
    ValidationReport report;
    const std::optional<TriangleFacts> surface = checkSurface(mesh, report);
    if (!surface || !mesh.hasUvs()) return report;
    const TriangleFacts& facts = *surface;
    checkDegenerateUv(mesh, facts, report);
    checkUvRange(mesh, facts, report);
    checkUvTiles(mesh, facts, report);
    checkUvOverlap(mesh, facts, report);
    checkUvMirrored(mesh, facts, report);
    checkUvDistortion(mesh, facts, report);
    report.mirroredSurfaceFraction = areaShare(mirroredTriangles(mesh), facts);
    return report;
}

}  // namespace plimsoll
