// The physics atlas (atlas.h).
//
// Charts grow from seed triangles across shared edges, best-aligned triangle first, while the
// triangle faces within the cone of the seed's normal and its projection onto the seed's plane
// overlaps no triangle already in the chart (exact clipped area, as in validation). The
// projection of a chart is then injective by construction, keeps every triangle's orientation
// (all face the axis), and stretches area by at most 1/cos(cone angle). Small charts left
// between big ones are absorbed by their neighbours under a wider cone, so that noisy meshes
// do not end up as confetti that packs badly. All charts share one scale, the largest at which
// a Tetris-like packer fits their outlines (with gutters) into the texture.
#include "plimsoll/surface/atlas.h"

#include "plimsoll/core/limits.h"

#include "core/printed.h"
#include "geometry/uv_clip.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numeric>
#include <queue>
#include <span>
#include <sstream>
#include <unordered_map>

namespace plimsoll {

namespace {

using uvclip::Point2;
using uvclip::UvTriangle;

constexpr std::uint32_t kUnassigned = ~0u;
// Charts below this share of the surface are offered to their neighbours.
constexpr double kSmallChartShare = 0.002;
// The cone a neighbour accepts absorbed triangles in: stretch at most 1/cos(75) = 3.9, still
// within the spread validation tolerates.
constexpr double kAbsorbAngleDegrees = 75.0;
// Overlap below this share of the mesh's mean triangle area is clipping rounding between
// neighbours that share an edge.
constexpr double kOverlapRounding = 1e-8;
// Bisection steps of the packing scale: within 2^-10 of the largest that fits.
constexpr int kBisections = 10;
// Cuts of long charts tried for a better coverage.
constexpr int kMaxSplits = 12;

// ---------------------------------------------------------------------------------------------
// Surface facts: unit normals, areas, and edge neighbours after welding by position.

struct SurfaceFacts {
    std::vector<Eigen::Vector3d> normal;  // unit, or zero for a degenerate triangle
    std::vector<double> area;
    std::vector<std::uint32_t> welded;  // per vertex
    // Neighbours across edges: neighbours[firstNeighbour[t] .. firstNeighbour[t + 1]).
    std::vector<std::uint32_t> firstNeighbour, neighbours;
    double totalArea = 0;
    double meanEdge = 0;

    std::span<const std::uint32_t> neighboursOf(std::uint32_t t) const {
        return {neighbours.data() + firstNeighbour[t], firstNeighbour[t + 1] - firstNeighbour[t]};
    }
};

SurfaceFacts surfaceFacts(const TriangleMesh& mesh) {
    SurfaceFacts f;
    const std::size_t n = mesh.triangleCount();
    f.normal.resize(n);
    f.area.resize(n);
    f.welded = weldByPosition(mesh);
    double edgeSum = 0;
    for (std::size_t t = 0; t < n; ++t) {
        const Eigen::Vector3d a = triangleAreaVector(mesh, mesh.triangles[t]);
        f.area[t] = a.norm();
        f.normal[t] = f.area[t] > 0 ? Eigen::Vector3d(a / f.area[t]) : Eigen::Vector3d::Zero();
        f.totalArea += f.area[t];
        const Triangle& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            edgeSum += (mesh.positions[tri[k]] - mesh.positions[tri[(k + 1) % 3]]).norm();
        }
    }
    f.meanEdge = n > 0 ? edgeSum / (3.0 * static_cast<double>(n)) : 0;

    // Edges as (smaller welded id, larger welded id, triangle), sorted: equal keys are neighbours
    // (more than two on a non-manifold edge: all of them).
    struct EdgeUse {
        std::uint64_t key;
        std::uint32_t triangle;
        bool operator<(const EdgeUse& o) const {
            return key != o.key ? key < o.key : triangle < o.triangle;
        }
    };
    std::vector<EdgeUse> edges;
    edges.reserve(3 * n);
    for (std::uint32_t t = 0; t < n; ++t) {
        const Triangle& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            std::uint64_t a = f.welded[tri[k]], b = f.welded[tri[(k + 1) % 3]];
            if (a == b) continue;
            if (a > b) std::swap(a, b);
            edges.push_back({(a << 32) | b, t});
        }
    }
    std::sort(edges.begin(), edges.end());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j].key == edges[i].key) ++j;
        for (std::size_t a = i; a < j; ++a) {
            for (std::size_t b = i; b < j; ++b) {
                if (edges[a].triangle != edges[b].triangle) {
                    pairs.emplace_back(edges[a].triangle, edges[b].triangle);
                }
            }
        }
        i = j;
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    f.firstNeighbour.assign(n + 1, 0);
    for (const auto& [a, b] : pairs) ++f.firstNeighbour[a + 1];
    std::partial_sum(f.firstNeighbour.begin(), f.firstNeighbour.end(), f.firstNeighbour.begin());
    f.neighbours.reserve(pairs.size());
    for (const auto& [a, b] : pairs) f.neighbours.push_back(b);
    return f;
}

// ---------------------------------------------------------------------------------------------
// A chart while it grows: its projection plane and a hashed grid of its projected triangles.

class Chart {
public:
    Chart(const Eigen::Vector3d& axis, const Eigen::Vector3d& origin, double cell)
        : axis_(axis), origin_(origin), cell_(cell) {
        // Right-handed (e1, e2, axis): a triangle facing the axis stays counter-clockwise.
        e1_ = axis.unitOrthogonal();
        e2_ = axis.cross(e1_);
    }

    const Eigen::Vector3d& axis() const { return axis_; }

    Point2 project(const Eigen::Vector3d& p) const {
        const Eigen::Vector3d d = p - origin_;
        return {d.dot(e1_), d.dot(e2_)};
    }

    UvTriangle projected(const TriangleMesh& mesh, const Triangle& tri) const {
        UvTriangle u;
        for (int k = 0; k < 3; ++k) {
            u.corners[static_cast<std::size_t>(k)] = project(mesh.positions[tri[k]]);
            u.box.extend(u.corners[static_cast<std::size_t>(k)]);
        }
        return u;
    }

    /// True when `candidate` overlaps no member by more than `rounding` (area, m^2).
    bool fits(const UvTriangle& candidate, double rounding) {
        ++stamp_;
        bool clear = true;
        forCells(candidate.box, [&](std::vector<std::uint32_t>& members) {
            for (std::uint32_t m : members) {
                if (!clear) return;
                if (visited_[m] == stamp_) continue;
                visited_[m] = stamp_;
                const UvTriangle& other = members_[m];
                if (!candidate.box.intersects(other.box)) continue;
                if (uvclip::intersectionArea(candidate, other) > rounding) clear = false;
            }
        });
        return clear;
    }

    void add(const UvTriangle& member) {
        const auto id = static_cast<std::uint32_t>(members_.size());
        members_.push_back(member);
        visited_.push_back(0);
        forCells(member.box, [&](std::vector<std::uint32_t>& cell) { cell.push_back(id); });
    }

private:
    template <class Visit>
    void forCells(const Eigen::AlignedBox2d& box, Visit visit) {
        const auto lo = (box.min() / cell_).array().floor().cast<long long>();
        const auto hi = (box.max() / cell_).array().floor().cast<long long>();
        for (long long y = lo.y(); y <= hi.y(); ++y) {
            for (long long x = lo.x(); x <= hi.x(); ++x) {
                visit(cells_[static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull ^
                             static_cast<std::uint64_t>(y)]);
            }
        }
    }

    Eigen::Vector3d axis_, origin_, e1_, e2_;
    double cell_;
    std::vector<UvTriangle> members_;
    std::vector<std::uint64_t> visited_;
    std::uint64_t stamp_ = 0;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

struct Charting {
    std::vector<std::uint32_t> chartOf;  // per triangle
    std::vector<Chart> charts;
};

// Grows one chart from `seed` within the cone cos(angle) >= minDot, taking triangles that are
// unassigned (or, when absorbing, belong to a chart in `donor`).
void grow(const TriangleMesh& mesh, const SurfaceFacts& facts, Charting& c, std::uint32_t id,
          std::vector<std::uint32_t> frontier, double minDot, double rounding,
          const std::vector<bool>* donor, double maxRadius) {
    Chart& chart = c.charts[id];
    const auto available = [&](std::uint32_t t) {
        return c.chartOf[t] == kUnassigned || (donor && (*donor)[c.chartOf[t]]);
    };
    // Best-aligned first (ties by index, for determinism).
    using Item = std::pair<double, std::uint32_t>;
    const auto worse = [](const Item& a, const Item& b) {
        return a.first != b.first ? a.first < b.first : a.second > b.second;
    };
    std::priority_queue<Item, std::vector<Item>, decltype(worse)> queue(worse);
    std::vector<std::uint32_t> refused;  // tried for this chart already
    const auto offer = [&](std::uint32_t t) {
        if (!available(t)) return;
        const double alignment = facts.area[t] > 0 ? facts.normal[t].dot(chart.axis()) : 1.0;
        if (alignment >= minDot) queue.emplace(alignment, t);
    };
    for (std::uint32_t t : frontier) {
        for (std::uint32_t n : facts.neighboursOf(t)) offer(n);
    }
    while (!queue.empty()) {
        const std::uint32_t t = queue.top().second;
        queue.pop();
        if (!available(t) || std::find(refused.begin(), refused.end(), t) != refused.end()) {
            continue;
        }
        const UvTriangle projected = chart.projected(mesh, mesh.triangles[t]);
        if (maxRadius > 0) {
            // By the centroid: a triangle longer than the radius (low-poly assets) still joins.
            const Point2 centroid =
                (projected.corners[0] + projected.corners[1] + projected.corners[2]) / 3.0;
            if (centroid.norm() > maxRadius) {
                refused.push_back(t);
                continue;
            }
        }
        // A degenerate triangle covers no area and overlaps nothing.
        if (facts.area[t] > 0 && !chart.fits(projected, rounding)) {
            refused.push_back(t);
            continue;
        }
        chart.add(projected);
        c.chartOf[t] = id;
        for (std::uint32_t n : facts.neighboursOf(t)) offer(n);
    }
}

Charting buildCharts(const TriangleMesh& mesh, const SurfaceFacts& facts,
                     const AtlasSettings& settings) {
    const std::size_t n = mesh.triangleCount();
    const double minDot = std::cos(settings.maxChartAngleDegrees * M_PI / 180.0);
    const double rounding = kOverlapRounding * facts.totalArea / static_cast<double>(n);
    const double cell = std::max(2.0 * facts.meanEdge, 1e-300);
    const double maxRadius = settings.maxChartRadius * std::sqrt(facts.totalArea);
    Charting c;
    c.chartOf.assign(n, kUnassigned);

    // Seeds: the largest unassigned triangle first; flat regions then become big charts.
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return facts.area[a] > facts.area[b];
    });
    std::size_t assigned = 0, lastReported = 0;
    for (std::uint32_t seed : order) {
        if (c.chartOf[seed] != kUnassigned) continue;
        const Eigen::Vector3d axis =
            facts.area[seed] > 0 ? facts.normal[seed] : Eigen::Vector3d::UnitY();
        const Triangle& tri = mesh.triangles[seed];
        const Eigen::Vector3d centre =
            (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.0;
        const auto id = static_cast<std::uint32_t>(c.charts.size());
        c.charts.emplace_back(axis, centre, cell);
        c.charts[id].add(c.charts[id].projected(mesh, tri));
        c.chartOf[seed] = id;
        // The reach grows with the seed, so that charts of big triangles get more than one.
        double seedReach = 0;
        for (std::uint32_t v : tri)
            seedReach = std::max(seedReach, (mesh.positions[v] - centre).norm());
        grow(mesh, facts, c, id, {seed}, minDot, rounding, nullptr,
             maxRadius > 0 ? maxRadius + 2.0 * seedReach : 0.0);
        assigned = static_cast<std::size_t>(std::count_if(c.chartOf.begin(), c.chartOf.end(),
                                                          [](auto x) { return x != kUnassigned; }));
        if (settings.progress && assigned - lastReported > n / 50) {
            settings.progress(0.6 * static_cast<double>(assigned) / static_cast<double>(n));
            lastReported = assigned;
        }
    }

    // Small charts go to their neighbours where those can take them flat and without overlap.
    std::vector<double> chartArea(c.charts.size(), 0.0);
    for (std::size_t t = 0; t < n; ++t) chartArea[c.chartOf[t]] += facts.area[t];
    std::vector<bool> small(c.charts.size(), false);
    for (std::size_t k = 0; k < c.charts.size(); ++k) {
        small[k] = chartArea[k] < kSmallChartShare * facts.totalArea;
    }
    std::vector<std::uint32_t> bigByArea;
    for (std::uint32_t k = 0; k < c.charts.size(); ++k) {
        if (!small[k]) bigByArea.push_back(k);
    }
    std::stable_sort(bigByArea.begin(), bigByArea.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return chartArea[a] > chartArea[b]; });
    const double absorbDot = std::cos(kAbsorbAngleDegrees * M_PI / 180.0);
    for (std::uint32_t k : bigByArea) {
        std::vector<std::uint32_t> members;
        for (std::uint32_t t = 0; t < n; ++t) {
            if (c.chartOf[t] == k) members.push_back(t);
        }
        grow(mesh, facts, c, k, members, std::min(minDot, absorbDot), rounding, &small, 0.0);
    }
    if (settings.progress) settings.progress(0.7);

    // Renumber the charts that still own triangles, in order of first triangle.
    std::vector<std::uint32_t> renumber(c.charts.size(), kUnassigned);
    std::uint32_t next = 0;
    for (std::uint32_t& chart : c.chartOf) {
        if (renumber[chart] == kUnassigned) renumber[chart] = next++;
        chart = renumber[chart];
    }
    std::vector<Chart> kept;
    kept.reserve(next);
    std::vector<std::uint32_t> oldOf(next);
    for (std::uint32_t k = 0; k < renumber.size(); ++k) {
        if (renumber[k] != kUnassigned) oldOf[renumber[k]] = k;
    }
    for (std::uint32_t k = 0; k < next; ++k) kept.push_back(std::move(c.charts[oldOf[k]]));
    c.charts = std::move(kept);
    return c;
}

// ---------------------------------------------------------------------------------------------
// Layout: each chart turned to its minimal-area bounding rectangle, landscape.

double cross2(const Point2& o, const Point2& a, const Point2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Andrew's monotone chain; counter-clockwise, no repeated points.
std::vector<Point2> convexHull(std::vector<Point2> points) {
    std::sort(points.begin(), points.end(), [](const Point2& a, const Point2& b) {
        return a.x() != b.x() ? a.x() < b.x() : a.y() < b.y();
    });
    if (points.size() < 3) return points;
    std::vector<Point2> hull(2 * points.size());
    std::size_t k = 0;
    for (const Point2& p : points) {
        while (k >= 2 && cross2(hull[k - 2], hull[k - 1], p) <= 0) --k;
        hull[k++] = p;
    }
    for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross2(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
        hull[k++] = points[i];
    }
    hull.resize(k - 1);
    return hull;
}

struct ChartLayout {
    std::vector<std::uint32_t> vertices;                  // atlas vertex ids of the chart
    std::vector<Point2> local;                            // their coordinates, m, from 0
    std::vector<std::array<std::uint32_t, 3>> triangles;  // indices into `local`
    double area = 0;                                      // projected, m^2
};

// Rotation (cos, sin) that puts the hull's minimal-area bounding rectangle on the axes: one of
// its sides lies on a hull edge.
Eigen::Matrix2d minimalRectangleRotation(const std::vector<Point2>& points) {
    const std::vector<Point2> hull = convexHull(points);
    Eigen::Matrix2d best = Eigen::Matrix2d::Identity();
    double bestArea = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const Point2 edge = hull[(i + 1) % hull.size()] - hull[i];
        if (edge.norm() <= 0) continue;
        const Point2 d = edge.normalized();
        Eigen::Matrix2d r;
        r << d.x(), d.y(), -d.y(), d.x();  // rotates d onto +x
        Eigen::AlignedBox2d box;
        for (const Point2& p : hull) box.extend(r * p);
        const double area = box.sizes().prod();
        if (area < bestArea - 1e-15 * std::abs(area)) {
            bestArea = area;
            best = r;
        }
    }
    return best;
}

// ---------------------------------------------------------------------------------------------
// Packing: charts, largest first, go to the lowest, then leftmost, position and quarter turn at
// which their texel footprint (grown by the gutter) meets no texel already taken: a bitmap
// packer, so small charts fill the holes of ring-shaped ones and the gaps beside curved ones.
// Bounding rectangles (stb_rect_pack) left 33-48% of the texture covered on the shared meshes,
// dropping outlines onto a horizon (Lévy et al.'s Tetris packer, LSCM 2002) 39-56%. All
// charts share one scale, the largest at which they fit, found by bisection.

Point2 quarterTurn(const Point2& p, int turns) {
    switch (turns & 3) {
        case 1:
            return {-p.y(), p.x()};
        case 2:
            return {-p.x(), -p.y()};
        case 3:
            return {p.y(), -p.x()};
        default:
            return p;
    }
}

// Rows of bits, 64 texels a word.
class BitRows {
public:
    BitRows(int width, int height)
        : width_(width),
          height_(height),
          words_((width + 63) / 64 + 1),
          bits_(static_cast<std::size_t>(words_) * height, 0) {}

    int width() const { return width_; }
    int height() const { return height_; }
    void set(int x, int y) { row(y)[x >> 6] |= std::uint64_t{1} << (x & 63); }
    bool get(int x, int y) const { return (row(y)[x >> 6] >> (x & 63)) & 1; }
    /// 64 bits of row y starting at bit x (bits past the width read as zero).
    std::uint64_t bitsAt(int x, int y) const {
        const std::uint64_t* r = row(y);
        const int shift = x & 63;
        const std::uint64_t low = r[x >> 6] >> shift;
        return shift == 0 ? low : low | (r[(x >> 6) + 1] << (64 - shift));
    }
    std::uint64_t word(int j, int y) const { return row(y)[j]; }
    int wordsUsed() const { return (width_ + 63) / 64; }

private:
    std::uint64_t* row(int y) { return bits_.data() + static_cast<std::size_t>(y) * words_; }
    const std::uint64_t* row(int y) const {
        return bits_.data() + static_cast<std::size_t>(y) * words_;
    }
    int width_, height_, words_;
    std::vector<std::uint64_t> bits_;
};

// A chart's texels at one scale and quarter turn (every texel a triangle touches, exactly: the
// triangles are clipped to each texel column), grown by the dilation.
struct Footprint {
    BitRows mask{1, 1};
    Point2 offset;  // texel coordinates in the mask = turned local * scale + offset
};

Footprint footprintOf(const ChartLayout& chart, double scale, int turns, int dilation) {
    std::vector<Point2> texel(chart.local.size());
    Eigen::AlignedBox2d box;
    for (std::size_t i = 0; i < texel.size(); ++i) {
        texel[i] = quarterTurn(chart.local[i], turns) * scale;
        box.extend(texel[i]);
    }
    Footprint f;
    f.offset = Point2::Constant(dilation) - box.min();
    for (Point2& p : texel) p += f.offset;
    const int width = std::max(1, static_cast<int>(std::ceil(box.sizes().x()))) + 2 * dilation;
    const int height = std::max(1, static_cast<int>(std::ceil(box.sizes().y()))) + 2 * dilation;
    BitRows touched(width, height);
    for (const auto& tri : chart.triangles) {
        uvclip::ClipPolygon polygon;
        for (std::uint32_t v : tri) polygon.push(texel[v]);
        const auto [xLo, xHi] =
            std::minmax({polygon.points[0].x(), polygon.points[1].x(), polygon.points[2].x()});
        const int c0 = std::max(0, static_cast<int>(std::floor(xLo)));
        const int c1 = std::min(width - 1, static_cast<int>(std::floor(xHi)));
        if (c0 == c1) {  // within one column (most triangles at physics-texture sizes)
            const auto [yLo, yHi] =
                std::minmax({polygon.points[0].y(), polygon.points[1].y(), polygon.points[2].y()});
            const int r0 = std::clamp(static_cast<int>(std::floor(yLo)), 0, height - 1);
            const int r1 = std::clamp(static_cast<int>(std::floor(yHi)), 0, height - 1);
            for (int r = r0; r <= r1; ++r) touched.set(c0, r);
            continue;
        }
        for (int c = c0; c <= c1; ++c) {
            // The triangle within the column strip c <= x <= c + 1 (half-plane clips): convex,
            // so it touches every texel between its lowest and highest point.
            uvclip::ClipPolygon strip = uvclip::clipLeftOf(polygon, Point2(c, 1), Point2(c, 0));
            strip = uvclip::clipLeftOf(strip, Point2(c + 1, 0), Point2(c + 1, 1));
            if (strip.size == 0) continue;
            double yLo = std::numeric_limits<double>::infinity(), yHi = -yLo;
            for (int i = 0; i < strip.size; ++i) {
                yLo = std::min(yLo, strip.points[static_cast<std::size_t>(i)].y());
                yHi = std::max(yHi, strip.points[static_cast<std::size_t>(i)].y());
            }
            const int r0 = std::clamp(static_cast<int>(std::floor(yLo)), 0, height - 1);
            const int r1 = std::clamp(static_cast<int>(std::floor(yHi)), 0, height - 1);
            for (int r = r0; r <= r1; ++r) touched.set(c, r);
        }
    }
    f.mask = BitRows(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            if (!touched.get(x, y)) continue;
            for (int dy = std::max(0, y - dilation); dy <= std::min(height - 1, y + dilation); ++dy)
                for (int dx = std::max(0, x - dilation); dx <= std::min(width - 1, x + dilation);
                     ++dx)
                    f.mask.set(dx, dy);
        }
    }
    return f;
}

// Rows in the order a collision is found soonest: coarse strides first (0, h/2, h/4, 3h/4,
// ...), so an obstacle anywhere under the chart is met after a few rows, not after h/2.
std::vector<int> probeOrder(int height) {
    std::vector<int> order;
    std::vector<bool> seen(static_cast<std::size_t>(height), false);
    for (int stride = std::bit_floor(static_cast<unsigned>(std::max(height, 1))); stride >= 1;
         stride /= 2) {
        for (int r = 0; r < height; r += stride) {
            if (!seen[static_cast<std::size_t>(r)]) {
                seen[static_cast<std::size_t>(r)] = true;
                order.push_back(r);
            }
        }
    }
    return order;
}

bool fitsAt(const BitRows& taken, const BitRows& mask, const std::vector<int>& rows, int x, int y) {
    for (int r : rows) {
        for (int j = 0; j < mask.wordsUsed(); ++j) {
            if (taken.bitsAt(x + 64 * j, y + r) & mask.word(j, r)) return false;
        }
    }
    return true;
}

struct Placement {
    int turns = 0;
    Point2 corner = Point2::Zero();  // texel coordinates = turned local * scale + corner
};

// Places every chart at `scale` (texels per metre) into a size x size texture, or fails.
bool packAt(double scale, const std::vector<ChartLayout>& charts,
            const std::vector<std::uint32_t>& order, int size, int dilation,
            std::vector<Placement>& placements) {
    placements.assign(charts.size(), Placement{});
    BitRows taken(size, size);
    for (std::uint32_t k : order) {
        int bestTop = std::numeric_limits<int>::max(), bestX = 0, bestY = 0, bestTurns = -1;
        Footprint best;
        for (int turns = 0; turns < 4; ++turns) {
            Footprint f = footprintOf(charts[k], scale, turns, dilation);
            const int w = f.mask.width(), h = f.mask.height();
            bool found = false;
            // Lowest top first: a candidate row y can only win while y + h < bestTop.
            // The lowest row of the mask and its first texel: a position whose texel under it
            // is taken fails at once, so runs of taken texels are skipped 64 at a time.
            int firstColumn = 0;
            while (!f.mask.get(firstColumn, 0)) ++firstColumn;
            const std::vector<int> rows = probeOrder(h);
            for (int y = 0; y + h <= size && y + h < bestTop && !found; ++y) {
                for (int x = 0; x + w <= size; ++x) {
                    const std::uint64_t under = taken.bitsAt(x + firstColumn, y);
                    if (under & 1) {
                        x += std::countr_one(under) - 1;  // the loop adds the last one
                        continue;
                    }
                    if (!fitsAt(taken, f.mask, rows, x, y)) continue;
                    bestTop = y + h;
                    bestX = x;
                    bestY = y;
                    bestTurns = turns;
                    found = true;
                    break;
                }
            }
            if (found) best = std::move(f);
        }
        if (bestTurns < 0) return false;
        for (int r = 0; r < best.mask.height(); ++r) {
            for (int c = 0; c < best.mask.width(); ++c) {
                if (best.mask.get(c, r)) taken.set(bestX + c, bestY + r);
            }
        }
        placements[k] = {bestTurns, best.offset + Point2(bestX, bestY)};
    }
    return true;
}

// The atlas before packing: vertices split per chart, each chart in its own plane, turned to
// its minimal-area bounding rectangle.
struct AtlasLayout {
    std::vector<std::uint32_t> sourceVertex;
    std::vector<Eigen::Vector3d> positions;
    std::vector<Triangle> triangles;
    std::vector<std::uint32_t> chartOf;
    std::vector<ChartLayout> charts;
};

AtlasLayout layOut(const TriangleMesh& mesh, const SurfaceFacts& facts,
                   const std::vector<Chart>& projections, const std::vector<std::uint32_t>& chartOf,
                   const std::vector<std::uint32_t>& projectionOf) {
    AtlasLayout layout;
    layout.chartOf = chartOf;
    layout.charts.resize(projectionOf.size());
    layout.triangles.resize(mesh.triangleCount());
    // One vertex per (chart, welded position), numbered in order of first use.
    std::unordered_map<std::uint64_t, std::uint32_t> vertexOf;
    std::vector<std::uint32_t> localIndex;  // per atlas vertex: its index in its chart
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const std::uint32_t chart = chartOf[t];
        const Chart& projection = projections[projectionOf[chart]];
        ChartLayout& target = layout.charts[chart];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t source = mesh.triangles[t][static_cast<std::size_t>(k)];
            const std::uint64_t key = (std::uint64_t{chart} << 32) | facts.welded[source];
            auto [it, inserted] =
                vertexOf.emplace(key, static_cast<std::uint32_t>(layout.sourceVertex.size()));
            if (inserted) {
                layout.sourceVertex.push_back(source);
                layout.positions.push_back(mesh.positions[source]);
                localIndex.push_back(static_cast<std::uint32_t>(target.vertices.size()));
                target.vertices.push_back(it->second);
                target.local.push_back(projection.project(mesh.positions[source]));
            }
            layout.triangles[t][static_cast<std::size_t>(k)] = it->second;
        }
        const Triangle& tri = layout.triangles[t];
        target.triangles.push_back({localIndex[tri[0]], localIndex[tri[1]], localIndex[tri[2]]});
        target.area += facts.area[t] * std::max(0.0, facts.normal[t].dot(projection.axis()));
    }
    for (ChartLayout& chart : layout.charts) {
        const Eigen::Matrix2d rotation = minimalRectangleRotation(chart.local);
        for (Point2& p : chart.local) p = rotation * p;
    }
    return layout;
}

struct Packing {
    double scale = 0;  // texels per metre
    std::vector<Placement> placements;
    double coverage = 0;  // UV area over the texture
};

// The largest scale at which the charts fit, by bisection.
std::optional<Packing> pack(const std::vector<ChartLayout>& charts, const AtlasSettings& settings,
                            double hint) {
    const int size = settings.textureSize;
    const int dilation = (settings.gutterTexels + 1) / 2;
    double area = 0;
    for (const ChartLayout& chart : charts) area += chart.area;
    std::vector<std::uint32_t> order(charts.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return charts[a].area > charts[b].area;
    });
    Packing packing;
    const auto fits = [&](double scale) {
        return packAt(scale, charts, order, size, dilation, packing.placements);
    };
    double high = size / std::sqrt(area);  // every texel covered: an upper bound
    double low = 0.5 * high;
    int steps = kBisections;
    if (hint > 0 && hint < high && fits(0.9 * hint)) {
        // After a cut the scale moves little: bracket it near the last one.
        low = 0.9 * hint;
        if (fits(std::min(high, 1.1 * hint)))
            low = std::min(high, 1.1 * hint);
        else
            high = 1.1 * hint;
        steps = kBisections - 3;
    } else {
        int halvings = 0;
        while (!fits(low)) {
            if (++halvings > 40) return std::nullopt;
            high = low;
            low *= 0.5;
        }
    }
    for (int i = 0; i < steps; ++i) {
        const double middle = 0.5 * (low + high);
        if (fits(middle))
            low = middle;
        else
            high = middle;
    }
    fits(low);
    packing.scale = low;
    packing.coverage = area * low * low / (static_cast<double>(size) * size);
    return packing;
}

// Cuts the chart with the longest bounding-rectangle side in two at the median of its
// triangles' centroids along that side. Both halves keep the chart's projection (a
// part of an injective projection is injective).
void splitLongestChart(const std::vector<ChartLayout>& charts, std::vector<std::uint32_t>& chartOf,
                       std::vector<std::uint32_t>& projectionOf) {
    std::uint32_t longest = 0;
    double longestSide = -1;
    int axis = 0;
    for (std::uint32_t k = 0; k < charts.size(); ++k) {
        Eigen::AlignedBox2d box;
        for (const Point2& p : charts[k].local) box.extend(p);
        if (charts[k].triangles.size() < 2) continue;
        const Point2 sides = box.sizes();
        const double side = sides.maxCoeff();
        if (side > longestSide) {
            longestSide = side;
            longest = k;
            axis = sides.x() >= sides.y() ? 0 : 1;
        }
    }
    if (longestSide < 0) return;
    const ChartLayout& chart = charts[longest];
    // Triangle t of the mesh is the i-th triangle of its chart, in mesh order.
    std::vector<std::uint32_t> members;
    for (std::uint32_t t = 0; t < chartOf.size(); ++t) {
        if (chartOf[t] == longest) members.push_back(t);
    }
    std::vector<std::pair<double, std::uint32_t>> along;  // centroid coordinate, member index
    for (std::uint32_t i = 0; i < members.size(); ++i) {
        const auto& tri = chart.triangles[i];
        along.emplace_back(
            (chart.local[tri[0]][axis] + chart.local[tri[1]][axis] + chart.local[tri[2]][axis]) /
                3.0,
            i);
    }
    std::sort(along.begin(), along.end());
    const auto next = static_cast<std::uint32_t>(projectionOf.size());
    projectionOf.push_back(projectionOf[longest]);
    for (std::size_t j = along.size() / 2; j < along.size(); ++j) {
        chartOf[members[along[j].second]] = next;
    }
}

}  // namespace

// ---------------------------------------------------------------------------------------------

const char* atlasModeName(AtlasMode mode) {
    switch (mode) {
        case AtlasMode::Mesh:
            return "mesh";
        case AtlasMode::Auto:
            return "auto";
        case AtlasMode::Generate:
            return "generate";
    }
    return "auto";
}

std::optional<AtlasMode> parseAtlasMode(std::string_view name) {
    for (AtlasMode mode : {AtlasMode::Mesh, AtlasMode::Auto, AtlasMode::Generate}) {
        if (name == atlasModeName(mode)) return mode;
    }
    return std::nullopt;
}

Result<PhysicsAtlas> generatePhysicsAtlas(const TriangleMesh& mesh, const AtlasSettings& settings) {
    const std::string& name = mesh.source;
    if (mesh.triangles.empty())
        return makeError(ErrorKind::invalidArgument, name + ": cannot make an atlas: no triangles");
    for (const Eigen::Vector3d& p : mesh.positions) {
        if (!p.allFinite())
            return makeError(ErrorKind::invalidArgument,
                             name + ": cannot make an atlas: non-finite positions");
    }
    if (settings.textureSize < kMinTextureSize || settings.textureSize > kMaxTextureSize) {
        return makeError(ErrorKind::limit,
                         printed("%s: atlas texture size %d is outside %d..%d", name.c_str(),
                                 settings.textureSize, kMinTextureSize, kMaxTextureSize));
    }
    if (settings.gutterTexels < 0 || settings.gutterTexels > settings.textureSize / 4) {
        return makeError(ErrorKind::invalidArgument,
                         printed("%s: atlas gutter of %d texels is outside 0..%d", name.c_str(),
                                 settings.gutterTexels, settings.textureSize / 4));
    }
    if (!(settings.maxChartAngleDegrees > 0 && settings.maxChartAngleDegrees < 90)) {
        return makeError(ErrorKind::invalidArgument,
                         name + ": the chart angle must lie strictly between 0 and 90 degrees");
    }
    const SurfaceFacts facts = surfaceFacts(mesh);
    if (!(facts.totalArea > 0))
        return makeError(ErrorKind::invalidArgument, name + ": cannot make an atlas: zero area");
    const Charting charting = buildCharts(mesh, facts, settings);

    // Charts are packed at the largest scale that fits; a chart that is long for the texture
    // (the strips of a hull, the ring of a torus's top) limits that scale and leaves space
    // unused, so the longest chart is cut in two while that raises the coverage.
    std::vector<std::uint32_t> chartOf = charting.chartOf;
    std::vector<std::uint32_t> projectionOf(charting.charts.size());
    std::iota(projectionOf.begin(), projectionOf.end(), 0u);
    std::optional<AtlasLayout> best;
    std::optional<Packing> bestPacking;
    int worse = 0;
    for (int split = 0; split <= kMaxSplits && worse < 2; ++split) {
        AtlasLayout layout = layOut(mesh, facts, charting.charts, chartOf, projectionOf);
        std::optional<Packing> packing =
            pack(layout.charts, settings, bestPacking ? bestPacking->scale : 0.0);
        if (settings.progress) settings.progress(0.7 + 0.3 * (split + 1) / (kMaxSplits + 1));
        if (!packing) break;
        splitLongestChart(layout.charts, chartOf, projectionOf);  // for the next round
        if (!bestPacking || packing->coverage > bestPacking->coverage) {
            best = std::move(layout);
            bestPacking = std::move(packing);
            worse = 0;
        } else {
            ++worse;
        }
    }
    if (!bestPacking) {
        return makeError(ErrorKind::limit,
                         printed("%s: the %zu charts of the physics atlas do not fit into a "
                                 "%d x %d texture with %d-texel gutters; use a larger texture",
                                 name.c_str(), charting.charts.size(), settings.textureSize,
                                 settings.textureSize, settings.gutterTexels));
    }

    PhysicsAtlas atlas;
    atlas.mesh.source = mesh.source;
    atlas.mesh.positions = std::move(best->positions);
    atlas.mesh.triangles = std::move(best->triangles);
    atlas.sourceVertex = std::move(best->sourceVertex);
    atlas.chartOfTriangle = std::move(best->chartOf);
    atlas.chartCount = best->charts.size();
    const int size = settings.textureSize;
    const double low = bestPacking->scale;
    atlas.mesh.uvs.resize(atlas.mesh.positions.size());
    for (std::size_t k = 0; k < best->charts.size(); ++k) {
        const ChartLayout& chart = best->charts[k];
        const Placement& placement = bestPacking->placements[k];
        for (std::size_t i = 0; i < chart.vertices.size(); ++i) {
            const Point2 texel =
                quarterTurn(chart.local[i], placement.turns) * low + placement.corner;
            atlas.mesh.uvs[chart.vertices[i]] = texel / size;
        }
    }
    atlas.uvPerMetre = low / size;
    for (const Triangle& t : atlas.mesh.triangles) {
        atlas.uvCoverage += std::abs(triangleUvArea(atlas.mesh, t));
    }
    if (settings.progress) settings.progress(1.0);
    return atlas;
}

std::string meshUvRefusal(const ValidationReport& report) {
    std::string reason;
    for (const Problem& p : report.problems) {
        if (p.severity != Severity::Error || !isUvProblem(p.kind)) continue;
        if (!reason.empty()) reason += "; ";
        reason += std::string(problemCode(p.kind)) + ": " + p.message;
    }
    return reason;
}

Result<AtlasChoice> chooseAtlas(const TriangleMesh& mesh, const ValidationReport& report,
                                AtlasMode mode, const AtlasSettings& settings,
                                const AtlasSource& source) {
    const std::string refusal = meshUvRefusal(report);
    if (mode == AtlasMode::Mesh) {
        if (!refusal.empty()) {
            return makeError(ErrorKind::invalidArgument,
                             mesh.source + ": atlas 'mesh': the mesh's UVs cannot be baked (" +
                                 refusal + "); use atlas 'auto' or 'generate'");
        }
        return AtlasChoice{mesh, false, 0, ""};
    }
    if (mode == AtlasMode::Auto && refusal.empty()) return AtlasChoice{mesh, false, 0, ""};
    Result<PhysicsAtlas> atlas =
        source ? source(mesh, settings) : generatePhysicsAtlas(mesh, settings);
    if (!atlas) return atlas.error();
    AtlasChoice choice;
    choice.generated = true;
    choice.chartCount = atlas->chartCount;
    const std::string summary =
        printed("a generated physics atlas (%zu charts, %.1f%% of the texture covered)",
                atlas->chartCount, 100.0 * atlas->uvCoverage);
    choice.notice = mode == AtlasMode::Generate
                        ? mesh.source + ": baking " + summary
                        : mesh.source + ": the mesh's UVs cannot be baked (" + refusal +
                              "); baking " + summary + " instead";
    choice.mesh = std::move(atlas->mesh);
    return choice;
}

}  // namespace plimsoll
