// The water graph's step (docs/design.md, "Water graph"): the state of a body's compartments
// and pipes, and what one step does to it: exchange through the permeable surface, then flow
// between nodes (findDischargeNode and Poiseuille's law, or diffusion), plus the water's mass
// properties. The engine (plimsoll::WaterGraphSimulation, engine/src/graph/graph.cpp) and the
// runtime library (plimsoll_runtime::WaterGraph) both compile this header, so the two step
// the same water. The engine's per-texel exchange pass keeps its own double-precision
// reference (exchange_reference.cpp, the oracle of the OpenCL kernel); exchangePass below is
// the same rule for the runtime, and tests/runtime holds the two together.
//
// Rounding: the engine computed these sums with Eigen before they moved here, and its
// trajectories are pinned (tests/scene/test_determinism.cpp). So every product below
// associates as Eigen's does for 3-vectors on x86-64 (SSE2): a strided row's dot product as
// a0 b0 + (a1 b1 + a2 b2), a matrix-vector product's rows 0 and 1 as (a0 b0 + a1 b1) + a2 b2
// and row 2 as a strided dot, R^T v and norms as (a0 b0 + a1 b1) + a2 b2.
#pragma once

#include "plimsoll_eval/graph_settings.hpp"
#include "plimsoll_eval/vec.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>
#include <vector>

namespace plimsoll_eval {

namespace graph_detail {

inline constexpr double kPi = 3.14159265358979323846;

/// The cube root rounded to the nearest double on every platform: libm's cbrt is only faithful
/// (within one unit in the last place, and the last bit differs between x86-64's and aarch64's
/// glibc), so of the two doubles around the true root the one whose cube is nearer x is
/// chosen, the cube's error taken exactly with fused multiply-adds.
inline double cbrtNearest(double x) {
    const double y = std::cbrt(x);
    if (!std::isfinite(y) || y == 0.0) return y;
    auto miss = [x](double c) {
        const double c2 = c * c, e2 = std::fma(c, c, -c2);
        const double c3 = c2 * c, e3 = std::fma(c2, c, -c3);
        return std::abs((c3 - x) + (e3 + e2 * c));
    };
    double best = y, bestMiss = miss(y);
    for (const double c : {std::nextafter(y, -HUGE_VAL), std::nextafter(y, HUGE_VAL)}) {
        const double m = miss(c);
        if (m < bestMiss) best = c, bestMiss = m;
    }
    return best;
}

/// Row i of R dotted with v, associated as Eigen's strided row dot product.
inline double rowDot(const Mat3& R, int i, const Vec3& v) {
    return R.m[i][0] * v.x + (R.m[i][1] * v.y + R.m[i][2] * v.z);
}

/// R v, associated as Eigen's Matrix3d * Vector3d (rows 0 and 1 as packets, row 2 scalar).
inline Vec3 rotate(const Mat3& R, const Vec3& v) {
    return {R.m[0][0] * v.x + R.m[0][1] * v.y + R.m[0][2] * v.z,
            R.m[1][0] * v.x + R.m[1][1] * v.y + R.m[1][2] * v.z, rowDot(R, 2, v)};
}

}  // namespace graph_detail

/// One compartment as the step sees it (object space, m and m^3).
struct GraphNodeState {
    Vec3 position;
    double capacity = 0;
    double water = 0;
    bool sealed = false;  ///< takes and passes no water
    Vec3 box;             ///< box edges; all zero: a sphere of the capacity
    bool isBox() const { return box.x > 0 && box.y > 0 && box.z > 0; }
};

/// One pipe, its ends as node indices.
struct GraphPipeState {
    std::uint32_t a = 0, b = 0;
    double radius = 0.01;  ///< m
    double length = 0;     ///< m; 0 = the distance between the nodes
    bool open = true;
};

/// Volume and first moment (about the box centre, world axes) of the part of a box below the
/// plane y = h.
struct ClippedVolume {
    double volume = 0;
    Vec3 moment;
};

namespace graph_detail {

/// Volume and first moment of the wetted triangle (a, b, c), all at or below y = h: the
/// divergence theorem with fields that vanish on the plane, by the edge-midpoint rule (exact
/// for these quadratic integrands). kMoment false: the volume alone (the same operations, so
/// the same bits, without the moment's).
template <bool kMoment = true>
inline void addWettedPiece(const Vec3& a, const Vec3& b, const Vec3& c, double h,
                           ClippedVolume& sums) {
    const Vec3 area = 0.5 * cross(b - a, c - a);
    const Vec3 mids[3] = {0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)};
    double height = 0;
    Vec3 field;
    for (const Vec3& m : mids) {
        const double below = m.y - h;
        height += below;
        // (y^2 - h^2)/2 factored, so no digits are lost when y and h are close.
        if constexpr (kMoment) field += Vec3{m.x * below, 0.5 * below * (m.y + h), m.z * below};
    }
    height /= 3.0;
    sums.volume += area.y * height;
    if constexpr (kMoment) {
        field = {field.x / 3.0, field.y / 3.0, field.z / 3.0};
        sums.moment += area.y * field;
    }
}

/// Clips the triangle to y <= h and adds the kept part (a triangle or a quadrilateral split
/// in two, same winding).
template <bool kMoment = true>
inline void addClippedTriangle(const Vec3& p0, const Vec3& p1, const Vec3& p2, double h,
                               ClippedVolume& sums) {
    const Vec3 p[3] = {p0, p1, p2};
    Vec3 polygon[4];
    int count = 0;
    for (int i = 0; i < 3; ++i) {
        const Vec3& a = p[i];
        const Vec3& b = p[(i + 1) % 3];
        const double da = a.y - h, db = b.y - h;
        if (da <= 0.0) polygon[count++] = a;
        // Only where the ends lie strictly on opposite sides (the division is then safe), from
        // the submerged end so that two triangles sharing the edge get the same point.
        if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
            const Vec3& wet = da < 0.0 ? a : b;
            const Vec3& dry = da < 0.0 ? b : a;
            const double dWet = wet.y - h, dDry = dry.y - h;
            Vec3 crossing = wet + (dWet / (dWet - dDry)) * (dry - wet);
            crossing.y = h;  // on the plane exactly, where the fields vanish
            polygon[count++] = crossing;
        }
    }
    if (count >= 3) addWettedPiece<kMoment>(polygon[0], polygon[1], polygon[2], h, sums);
    if (count == 4) addWettedPiece<kMoment>(polygon[0], polygon[2], polygon[3], h, sums);
}

}  // namespace graph_detail

/// A box of edges `size`, centred at the origin, rotated by R: its twelve triangles in the
/// engine's box mesh order (plimsoll::makeBox: faces +x, -x, +y, -y, +z, -z, each split along
/// its first diagonal), so the sums add in the same order. Rotated once, clipped at as many
/// levels as a level search asks.
struct RotatedBox {
    Vec3 corner[6][4];  ///< per face, its four corners (world axes about the centre)

    RotatedBox() = default;
    RotatedBox(const Vec3& size, const Mat3& R) {
        // Per face: outward normal, u, v (u x v = normal), as signs per axis.
        struct Face {
            int n[3], u[3], v[3];
        };
        static constexpr Face kFaces[6] = {
            {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
            {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
            {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}}};
        static constexpr int kCorners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        const Vec3 half = 0.5 * size;
        for (int face = 0; face < 6; ++face) {
            const Face& f = kFaces[face];
            for (int k = 0; k < 4; ++k) {
                const int su = 2 * kCorners[k][0] - 1, sv = 2 * kCorners[k][1] - 1;
                const Vec3 p{(f.n[0] + su * f.u[0] + sv * f.v[0]) * half.x,
                             (f.n[1] + su * f.u[1] + sv * f.v[1]) * half.y,
                             (f.n[2] + su * f.u[2] + sv * f.v[2]) * half.z};
                corner[face][k] = graph_detail::rotate(R, p);
            }
            // Per triangle, what a wholly wet one adds with, worked out as addWettedPiece does.
            const Vec3* c = corner[face];
            const Vec3 tri[2][3] = {{c[0], c[1], c[2]}, {c[0], c[2], c[3]}};
            for (int t = 0; t < 2; ++t) {
                Triangle& out = triangle[2 * face + t];
                const Vec3 &a = tri[t][0], &b = tri[t][1], &d = tri[t][2];
                out.areaY = (0.5 * cross(b - a, d - a)).y;
                out.midY[0] = (0.5 * (a + b)).y;
                out.midY[1] = (0.5 * (b + d)).y;
                out.midY[2] = (0.5 * (d + a)).y;
                out.lowest = std::min({a.y, b.y, d.y});
                out.highest = std::max({a.y, b.y, d.y});
            }
        }
    }

    /// The part below y = h (kMoment false: its volume only, moment left zero). The volume
    /// alone takes a wholly wet triangle's sum from its kept terms and skips a dry one: the
    /// same operations in the same order as addClippedTriangle, so the same bits.
    template <bool kMoment = true>
    ClippedVolume below(double h) const {
        ClippedVolume sums;
        for (int face = 0; face < 6; ++face) {
            const Vec3* c = corner[face];
            for (int t = 0; t < 2; ++t) {
                const Triangle& tri = triangle[2 * face + t];
                if (!kMoment && tri.highest <= h) {  // every corner at or below h
                    double height = 0;
                    for (const double m : tri.midY) height += m - h;
                    height /= 3.0;
                    sums.volume += tri.areaY * height;
                    continue;
                }
                if (!kMoment && tri.lowest > h) continue;  // every corner above h: nothing
                graph_detail::addClippedTriangle<kMoment>(c[0], c[t + 1], c[t + 2], h, sums);
            }
        }
        return sums;
    }

private:
    struct Triangle {
        double areaY = 0, midY[3] = {0, 0, 0}, lowest = 0, highest = 0;
    };
    Triangle triangle[12];
};

/// The part of a box of edges `size`, centred at the origin and rotated by R, below y = h.
inline ClippedVolume clipBoxBelow(const Vec3& size, const Mat3& R, double h) {
    return RotatedBox(size, R).below(h);
}

/// The share of the unit cube where m1 v1 + m2 v2 + m3 v3 <= a, for 0 <= m1 <= m2 <= m3 with
/// m1 + m2 + m3 = 1 and a in [0, 1] (R. Scardovelli, S. Zaleski, "Analytical relations
/// connecting linear interfaces and volume fractions in rectangular grids", J. Comput. Phys.
/// 164, 2000): a piecewise cubic, taken for a <= 1/2 and mirrored above. Written so that no
/// piece divides by m1 what is not of order m1^3 (a body floating level has m1 and m2 near or
/// at zero); only +, -, *, / and comparisons, so the same bits on every platform.
inline double cubeShareBelow(double m1, double m2, double m3, double a) {
    const bool upper = a > 0.5;
    if (upper) a = 1.0 - a;
    const double m12 = m1 + m2;
    double v;
    if (a < m1) {  // a corner cut off (m1 > 0 here)
        v = a * a * a / (6.0 * m1 * m2 * m3);
    } else if (a < m2) {  // past the first corner: (a^3 - (a - m1)^3) / (6 m1 m2 m3)
        v = (3.0 * a * (a - m1) + m1 * m1) / (6.0 * m2 * m3);
    } else if (a < m12) {
        // Past the second corner (m1 > 0 here), and past the third where a >= m3 (then
        // m3 < 1/2 < m1 + m2): each adds -(a - m_i)^3 / (6 m1 m2 m3), with a - m_i < m1.
        const double b = a - m2;
        double cut = b * b * b;
        if (a >= m3) {
            const double c = a - m3;
            cut += c * c * c;
        }
        v = (3.0 * a * (a - m1) + m1 * m1 - cut / m1) / (6.0 * m2 * m3);
    } else {  // a in [m1 + m2, 1/2], so m3 >= 1/2 >= m1 + m2: a slab across the short edges
        v = (2.0 * a - m12) / (2.0 * m3);
    }
    return upper ? 1.0 - v : v;
}

/// A box of edges `size` centred at the origin, rotated by R, as its volume below world
/// levels needs it: the edges' spans along the vertical, sorted, and their sum.
struct BoxSpans {
    double m[3] = {0, 0, 0};  ///< size_i |R_1i|, ascending, over their sum
    double span = 0;          ///< their sum: the box's height in world axes
    double volume = 0;        ///< size.x size.y size.z

    BoxSpans() = default;
    BoxSpans(const Vec3& size, const Mat3& R) {
        double e[3] = {size.x * std::abs(R.m[1][0]), size.y * std::abs(R.m[1][1]),
                       size.z * std::abs(R.m[1][2])};
        if (e[0] > e[1]) std::swap(e[0], e[1]);
        if (e[1] > e[2]) std::swap(e[1], e[2]);
        if (e[0] > e[1]) std::swap(e[0], e[1]);
        span = e[0] + e[1] + e[2];
        for (int i = 0; i < 3; ++i) m[i] = e[i] / span;
        volume = size.x * size.y * size.z;
    }
    /// The volume below a level `offset` above the centre (world axes): the box's points u with
    /// sum_i R_1i u_i <= offset are, with each edge's coordinate v_i in 0..1 taken from its
    /// lower end, those where sum_i m_i v_i <= offset / span + 1/2.
    double below(double offset) const {
        const double a = std::clamp(offset / span + 0.5, 0.0, 1.0);
        return volume * cubeShareBelow(m[0], m[1], m[2], a);
    }
};

/// A bracket [lo, hi] of the root of an increasing f: f(lo) < 0 <= f(hi).
struct RootBracket {
    double lo = 0, hi = 0;
};

/// Brent's method (R. P. Brent, "Algorithms for Minimization without Derivatives", 1973,
/// ch. 4, zeroin) for an increasing f from a bracket with f(lo) = fLo < 0 <= f(hi) = fHi: inverse
/// quadratic interpolation and secant steps kept inside the bracket, bisection where they
/// stall, and steps of at least `tolerance(b)` / 2, so that the bracket it returns (f(lo) < 0
/// <= f(hi), the sides as a bisection on `f(mid) < 0` keeps them) is at most tolerance(b) wide
/// (b its better end), as a bisection's stopping rule. f = 0 met exactly: lo = hi = that point.
/// Only
/// +, -, *, / and comparisons: the same steps on every platform. A box's volume below a level
/// is piecewise cubic and C1, where this takes about 6 to 10 evaluations against a bisection's
/// 40 to 50.
template <class F, class Tolerance>
RootBracket bracketRoot(F&& f, double lo, double hi, double fLo, double fHi, Tolerance&& tolerance,
                        int maxEvaluations = 200) {
    double a = lo, fa = fLo, b = hi, fb = fHi, c = a, fc = fa;
    double d = b - a, e = d;
    auto negative = [](double v) { return v < 0.0; };
    for (int evaluation = 0;; ++evaluation) {
        if (negative(fb) == negative(fc)) {  // c: the other side of the root from b
            c = a;
            fc = fa;
            d = e = b - a;
        }
        if (std::abs(fc) < std::abs(fb)) {  // b: the better estimate
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        const double tol1 = 0.5 * tolerance(b);
        const double xm = 0.5 * (c - b);
        if (fb == 0.0) return {b, b};
        if (std::abs(xm) <= tol1 || evaluation >= maxEvaluations)
            return negative(fb) ? RootBracket{b, c} : RootBracket{c, b};
        if (std::abs(e) >= tol1 && std::abs(fa) > std::abs(fb)) {
            double p, q;
            const double s = fb / fa;
            if (a == c) {  // secant
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {  // inverse quadratic interpolation
                const double qa = fa / fc, r = fb / fc;
                p = s * (2.0 * xm * qa * (qa - r) - (b - a) * (r - 1.0));
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if (p > 0.0)
                q = -q;
            else
                p = -p;
            const double previous = e;
            e = d;
            if (2.0 * p < 3.0 * xm * q - std::abs(tol1 * q) && p < std::abs(0.5 * previous * q)) {
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += std::abs(d) > tol1 ? d : (xm > 0.0 ? tol1 : -tol1);
        fb = f(b);
    }
}

/// The node a surface point feeds (paper 4.2): plimsoll_eval/nearest_node.hpp.

/// A permeable surface point: where it is (object space), permeability x area (m^2) and the
/// node it feeds.
struct ExchangePoint {
    Vec3 position;
    double weight = 0;
    std::uint32_t node = 0;
};

/// Per-node rates of one exchange pass (m^3/s) and the highest outside surface feeding each
/// node (world m; -inf: none).
struct ExchangeRates {
    std::vector<double> inflow, outflow, outsideTop;
};

/// World positions of `points` for the body at (R, origin): where the exchange pass asks the
/// water's height, all at once.
inline void exchangePositions(const std::vector<ExchangePoint>& points, const Mat3& R,
                              const Vec3& origin, std::vector<Vec3>& world) {
    world.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
        world[i] = graph_detail::rotate(R, points[i].position) + origin;
}

/// The world heights alone of exchangePositions (the same bits): all flat water needs.
inline void exchangeHeights(const std::vector<ExchangePoint>& points, const Mat3& R, double originY,
                            std::vector<double>& y) {
    y.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3& p = points[i].position;
        y[i] = (R.m[1][0] * p.x + R.m[1][1] * p.y + R.m[1][2] * p.z) + originY;
    }
}

/// The outside water the exchange sees: the water's heights on a world lattice of spacing
/// kExchangeLatticeSpacing (nodes at (i s, j s)), interpolated bilinearly between the four
/// nodes about each point. A body's permeable points crowd into few cells (an opening's texels
/// lie a few centimetres apart, a hull side's above one another), so the water answers one
/// height per lattice node they touch rather than one per point; the interpolant's error is at
/// most s^2 / 8 times the water's curvature (docs/design.md, "Water graph"). Flat water needs
/// no lattice: the interpolant of a constant is that constant.
inline constexpr double kExchangeLatticeSpacing = 0.25;  ///< m

/// A point's lattice cell (its lower nodes i, j) and where it lies in it (0..1 along x, z).
struct LatticeCell {
    std::int64_t i = 0, j = 0;
    double tx = 0, tz = 0;
};

inline LatticeCell latticeCell(double x, double z, double spacing) {
    double gx = x / spacing, gz = z / spacing;
    // A point beyond any water (or NaN) takes the cell at the origin: the integer conversion
    // stays defined, and its height is as meaningless as the position.
    constexpr double kFar = 4.0e15;
    if (!(std::abs(gx) < kFar)) gx = 0.0;
    if (!(std::abs(gz) < kFar)) gz = 0.0;
    // The floor by truncation, less one below a negative fraction: exact here (|g| < 2^52),
    // the same bits as std::floor, which baseline x86-64 has no instruction for.
    std::int64_t i = static_cast<std::int64_t>(gx), j = static_cast<std::int64_t>(gz);
    i -= static_cast<double>(i) > gx ? 1 : 0;
    j -= static_cast<double>(j) > gz ? 1 : 0;
    return {i, j, gx - static_cast<double>(i), gz - static_cast<double>(j)};
}

/// Bilinear interpolation of the cell's node heights (f00 at (i, j), f10 at (i + 1, j), ...),
/// as differences from the lower nodes, so equal heights give that height exactly.
inline double latticeInterpolate(double f00, double f10, double f01, double f11, double tx,
                                 double tz) {
    const double a = f00 + tx * (f10 - f00);
    const double b = f01 + tx * (f11 - f01);
    return a + tz * (b - a);
}

/// Scratch of exchangeSurfaces, kept between steps (no allocation once sized).
struct ExchangeLattice {
    /// Per point, its cell (latticeCell) a field an array: a point's two 8-byte indices written
    /// as one 16-byte copy made every next read of them wait for the store (a store-forwarding
    /// stall that was a quarter of the runtime's exchange pass).
    std::vector<std::int64_t> cellI, cellJ;
    std::vector<double> cellX, cellZ;
    std::vector<std::uint32_t> corners;  ///< per point, its four nodes' indices in x, z
    std::vector<std::int32_t> slot;      ///< per node of the cells' bounding box; -1: not asked
    std::map<std::pair<std::int64_t, std::int64_t>, std::int32_t> sparse;  ///< beyond: node, slot
    std::vector<double> x, z, height;  ///< the nodes asked, in the order first touched
};

/// The outside surface over each of the world points `world`: one call
/// heights(n, x, z, out) for the lattice nodes the points touch (each once), then per point
/// latticeInterpolate. The nodes are asked in the order the points first touch them.
template <class Heights>
void exchangeSurfaces(const std::vector<Vec3>& world, double spacing, Heights&& heights,
                      ExchangeLattice& lattice, std::vector<double>& surface) {
    const std::size_t n = world.size();
    surface.resize(n);
    lattice.x.clear();
    lattice.z.clear();
    if (n == 0) return;
    lattice.cellI.resize(n);
    lattice.cellJ.resize(n);
    lattice.cellX.resize(n);
    lattice.cellZ.resize(n);
    lattice.corners.resize(4 * n);
    std::int64_t* cellI = lattice.cellI.data();
    std::int64_t* cellJ = lattice.cellJ.data();
    std::int64_t i0 = 0, i1 = 0, j0 = 0, j1 = 0;
    for (std::size_t p = 0; p < n; ++p) {
        const LatticeCell c = latticeCell(world[p].x, world[p].z, spacing);
        cellI[p] = c.i;
        cellJ[p] = c.j;
        lattice.cellX[p] = c.tx;
        lattice.cellZ[p] = c.tz;
        if (p == 0) {
            i0 = i1 = c.i;
            j0 = j1 = c.j;
        }
        i0 = std::min(i0, c.i), i1 = std::max(i1, c.i);
        j0 = std::min(j0, c.j), j1 = std::max(j1, c.j);
    }
    // The nodes of the cells' bounding box, indexed densely while that stays small against the
    // points (a body a few hundred cells across); beyond (points kilometres apart), by a map.
    const double across = double(i1 - i0) + 2.0, along = double(j1 - j0) + 2.0;
    const bool dense = across * along <= 8.0 * double(n) + 4096.0;
    const std::int64_t stride = i1 - i0 + 2;
    if (dense) {
        lattice.slot.assign(static_cast<std::size_t>(across * along), -1);
    } else {
        lattice.sparse.clear();
    }
    auto node = [&](std::int64_t i, std::int64_t j) -> std::uint32_t {
        const auto next = static_cast<std::int32_t>(lattice.x.size());
        if (dense) {
            std::int32_t& s = lattice.slot[static_cast<std::size_t>((j - j0) * stride + (i - i0))];
            if (s >= 0) return static_cast<std::uint32_t>(s);
            s = next;
        } else if (const auto [at, added] = lattice.sparse.try_emplace({i, j}, next); !added) {
            return static_cast<std::uint32_t>(at->second);
        }
        lattice.x.push_back(double(i) * spacing);
        lattice.z.push_back(double(j) * spacing);
        return static_cast<std::uint32_t>(lattice.x.size() - 1);
    };
    // Neighbouring points mostly share a cell: its nodes as the previous point found them,
    // kept here rather than read back from the point's just-written corners.
    std::uint32_t last[4] = {0, 0, 0, 0};
    for (std::size_t p = 0; p < n; ++p) {
        const std::int64_t i = cellI[p], j = cellJ[p];
        if (p == 0 || i != cellI[p - 1] || j != cellJ[p - 1]) {
            last[0] = node(i, j);
            last[1] = node(i + 1, j);
            last[2] = node(i, j + 1);
            last[3] = node(i + 1, j + 1);
        }
        std::uint32_t* k = &lattice.corners[4 * p];
        for (int m = 0; m < 4; ++m) k[m] = last[m];
    }
    const std::size_t asked = lattice.x.size();
    lattice.height.resize(asked);
    heights(asked, lattice.x.data(), lattice.z.data(), lattice.height.data());
    const double* f = lattice.height.data();
    for (std::size_t p = 0; p < n; ++p) {
        const std::uint32_t* k = &lattice.corners[4 * p];
        surface[p] = latticeInterpolate(f[k[0]], f[k[1]], f[k[2]], f[k[3]], lattice.cellX[p],
                                        lattice.cellZ[p]);
    }
}

/// The exchange pass over `points` at world heights y[i], with the water surface surface(i)
/// above point i: the outside depth d_out = max(0, f - y) against the inside head
/// d_in = max(0, surface_n - y) drives |q| = factor w |h| (linear) or factor w sqrt|h|
/// (Torricelli), h = d_out - d_in > 0 in.
template <class Surface>
inline void exchangePass(const std::vector<ExchangePoint>& points, const double* y,
                         Surface&& surface, std::size_t nodes, const double* nodeSurface,
                         bool torricelli, double factor, ExchangeRates& rates) {
    rates.inflow.assign(nodes, 0.0);
    rates.outflow.assign(nodes, 0.0);
    rates.outsideTop.assign(nodes, -std::numeric_limits<double>::infinity());
    // The points of one node come in runs: a run's sums are kept in registers and stored when
    // the node changes (adding to what the node already holds, in the same order: the same
    // bits as adding into the arrays point by point, without each add waiting on the last
    // one's store).
    if (points.empty()) return;
    std::size_t node = points[0].node;
    double in = 0, out = 0, top = -std::numeric_limits<double>::infinity();  // as assigned
    const auto store = [&] {
        rates.inflow[node] = in;
        rates.outflow[node] = out;
        rates.outsideTop[node] = top;
    };
    for (std::size_t i = 0; i < points.size(); ++i) {
        const ExchangePoint& s = points[i];
        if (s.node != node) {
            store();
            node = s.node;
            in = rates.inflow[node];
            out = rates.outflow[node];
            top = rates.outsideTop[node];
        }
        const double f = surface(i);
        const double outside = std::max(0.0, f - y[i]);
        const double inside = std::max(0.0, nodeSurface[node] - y[i]);
        const double head = outside - inside;
        if (head == 0) continue;
        const double q = torricelli ? factor * s.weight * std::sqrt(std::abs(head))
                                    : factor * s.weight * std::abs(head);
        if (head > 0) {
            in += q;
            top = std::max(top, f);
        } else {
            out += q;
        }
    }
    store();
}

/// Mass properties of the water (object space; inertia about its centre of mass, products
/// with the minus sign).
struct WaterMass {
    double mass = 0;    ///< kg
    double volume = 0;  ///< m^3
    Vec3 centerOfMass;
    double inertia[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
};

/// Water bookkeeping since the start (m^3): entered + initial = stored + left, to rounding.
struct GraphFlowTotals {
    double entered = 0;  ///< through the surface, into nodes
    double left = 0;     ///< through the surface, out of nodes
    double initial = 0;  ///< in the nodes at the start
    double moved = 0;    ///< between nodes (not a balance term)
};

/// A body's water graph and its state, stepped with the body's rotation R (object -> world).
class GraphFlow {
public:
    /// Takes the nodes and pipes (valid: capacities > 0, pipes between distinct nodes) and
    /// starts the random sequence (splitmix64) at `seed`. Pipes that are closed or touch a
    /// sealed node pass nothing.
    void reset(std::vector<GraphNodeState> nodes, std::vector<GraphPipeState> pipes,
               std::uint64_t seed) {
        nodes_ = std::move(nodes);
        pipes_ = std::move(pipes);
        rng_ = seed;
        totals_ = {};
        memo_.clear();
        const std::size_t n = nodes_.size();
        links_.assign(n, {});
        radius_.assign(n, 0.0);
        scaledBox_.assign(n, Vec3{});
        for (std::size_t i = 0; i < n; ++i) {
            const GraphNodeState& node = nodes_[i];
            radius_[i] = graph_detail::cbrtNearest(3.0 * node.capacity / (4.0 * graph_detail::kPi));
            if (node.isBox()) {
                // The box scaled to hold exactly the node's capacity.
                const double volume = node.box.x * node.box.y * node.box.z;
                scaledBox_[i] = graph_detail::cbrtNearest(node.capacity / volume) * node.box;
            }
            totals_.initial += node.water;
        }
        length_.assign(pipes_.size(), 0.0);
        for (std::size_t p = 0; p < pipes_.size(); ++p) {
            const GraphPipeState& pipe = pipes_[p];
            length_[p] = pipe.length > 0 ? pipe.length
                                         : norm(nodes_[pipe.a].position - nodes_[pipe.b].position);
            if (!pipe.open || nodes_[pipe.a].sealed || nodes_[pipe.b].sealed) continue;
            links_[pipe.a].push_back({pipe.b, static_cast<std::uint32_t>(p)});
            links_[pipe.b].push_back({pipe.a, static_cast<std::uint32_t>(p)});
        }
    }

    const std::vector<GraphNodeState>& nodes() const { return nodes_; }
    const GraphFlowTotals& totals() const { return totals_; }
    /// The random sequence's position (part of state()).
    std::uint64_t randomState() const { return rng_; }
    /// Heap bytes the state holds beyond sizeof(GraphFlow).
    std::size_t memoryBytes() const {
        std::size_t bytes =
            nodes_.capacity() * sizeof(GraphNodeState) +
            pipes_.capacity() * sizeof(GraphPipeState) +
            (length_.capacity() + radius_.capacity() + levels_.capacity()) * sizeof(double) +
            scaledBox_.capacity() * sizeof(Vec3) + pathOrder_.capacity() * sizeof(Link) +
            pathStack_.capacity() * sizeof(PathFrame) + memo_.capacity() * sizeof(LevelMemo) +
            links_.capacity() * sizeof(std::vector<Link>);
        for (const std::vector<Link>& links : links_) bytes += links.capacity() * sizeof(Link);
        return bytes;
    }
    double storedWater() const {
        double sum = 0;
        for (const GraphNodeState& n : nodes_) sum += n.water;
        return sum;
    }
    /// What changes as the graph steps: each node's water, the random sequence's position and
    /// the bookkeeping. Restoring what was saved continues the steps bit for bit.
    struct State {
        std::vector<double> water;
        std::uint64_t random = 0;
        GraphFlowTotals totals;
    };
    State state() const {
        State s;
        s.water.reserve(nodes_.size());
        for (const GraphNodeState& n : nodes_) s.water.push_back(n.water);
        s.random = rng_;
        s.totals = totals_;
        return s;
    }
    /// False (and nothing changed) when `s` holds another node count.
    bool restore(const State& s) {
        if (s.water.size() != nodes_.size()) return false;
        for (std::size_t i = 0; i < nodes_.size(); ++i) nodes_[i].water = s.water[i];
        rng_ = s.random;
        totals_ = s.totals;
        return true;
    }
    /// Sets a node's water (clamped to 0..capacity), booked as initial water.
    void setWater(std::size_t node, double water) {
        GraphNodeState& n = nodes_[node];
        const double clamped = std::clamp(water, 0.0, n.capacity);
        totals_.initial += clamped - n.water;
        n.water = clamped;
    }

    /// Poiseuille's law: pi dp r^4 / (8 mu L), m^3/s.
    static double poiseuilleRate(double dp, double radius, double viscosity, double length) {
        // r^4 as two products (exact rounding on every platform; pow is only nearly so).
        const double r2 = radius * radius;
        return graph_detail::kPi * dp * (r2 * r2) / (8.0 * viscosity * length);
    }

    /// World height of node i's position above the body's origin.
    double nodeHeight(std::size_t node, const Mat3& R) const {
        return graph_detail::rowDot(R, 1, nodes_[node].position);
    }

    /// Node i's water volume below world levels about its position, for one rotation (a box
    /// node's corners rotated once for the many levels a search asks).
    class NodeVolume {
    public:
        NodeVolume(const GraphFlow& flow, std::size_t node, const Mat3& R)
            : node_(&flow.nodes_[node]),
              radius_(flow.radius_[node]),
              R_(&R),
              size_(flow.scaledBox_[node]) {
            if (node_->isBox()) spans_ = BoxSpans(size_, R);
        }
        /// Water volume up to a world level `offset` above the node's position (0..capacity):
        /// a box's in closed form (BoxSpans), which the level searches ask most of the step's
        /// time for; it agrees with the box clipped (clip) to rounding.
        double operator()(double offset) const {
            if (!node_->isBox()) {
                const double r = radius_;
                const double h = std::clamp(offset + r, 0.0, 2.0 * r);
                return std::clamp(graph_detail::kPi * h * h * (3.0 * r - h) / 3.0, 0.0,
                                  node_->capacity);
            }
            const double v = spans_.below(offset);
            return std::isfinite(v) ? std::clamp(v, 0.0, node_->capacity) : 0.0;
        }
        /// A box node's water below `offset` with its first moment (world axes about the centre).
        ClippedVolume clip(double offset) const { return RotatedBox(size_, *R_).below(offset); }

    private:
        const GraphNodeState* node_;
        double radius_;
        const Mat3* R_;
        Vec3 size_;
        BoxSpans spans_;
    };

    /// Water volume of node i up to a world level `offset` above its position (0..capacity).
    double volumeAtLevel(std::size_t node, double offset, const Mat3& R) const {
        return NodeVolume(*this, node, R)(offset);
    }

    /// Lowest and highest world offsets of node i's compartment about its position.
    std::pair<double, double> levelRange(std::size_t node, const Mat3& R) const {
        if (!nodes_[node].isBox()) return {-radius_[node], radius_[node]};
        const Vec3 half = 0.5 * scaledBox_[node];
        const double reach = std::abs(R.m[1][0]) * half.x +
                             (std::abs(R.m[1][1]) * half.y + std::abs(R.m[1][2]) * half.z);
        return {-reach, reach};
    }

    /// The tolerance of a level search about level x (m): the bracket it ends with is at most
    /// this wide, and the level its midpoint.
    static double levelTolerance(double x) { return 1e-12 * (1.0 + std::abs(x)); }

    /// Level of `water` in node i: world height above its position, where volumeAtLevel reaches
    /// `water` (bracketRoot: within levelTolerance / 2 of the root, as the bisection that
    /// levelOffsetBisection keeps as the reference). An empty node's level is its lowest point.
    double levelOffset(std::size_t node, double water, const Mat3& R) const {
        return levelOffset(NodeVolume(*this, node, R), node, water, R);
    }

    /// levelOffset by bisection on volumeAtLevel (how the step found levels before bracketRoot,
    /// 40 to 50 volumes a level): the reference the tests hold levelOffset to.
    double levelOffsetBisection(std::size_t node, double water, const Mat3& R) const {
        auto [lo, hi] = levelRange(node, R);
        if (water <= 0) return lo;
        if (water >= nodes_[node].capacity) return hi;
        for (int it = 0; it < 50 && hi - lo > levelTolerance(hi); ++it) {
            const double mid = 0.5 * (lo + hi);
            (volumeAtLevel(node, mid, R) < water ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    }

    /// Node i's water surface relative to the body's origin (world axes).
    double level(std::size_t node, const Mat3& R) const {
        return nodeHeight(node, R) + currentOffset(node, R);
    }

    /// Works out every node's level at R once and keeps it with the water it holds, for the
    /// step's searches at the same R (a level is a function of the water and R alone, so a
    /// kept one is the bits a new search would give: nothing of it is state).
    void prepareLevels(const Mat3& R) {
        for (std::size_t i = 0; i < nodes_.size(); ++i) memoLevel(i, R);
    }

    /// World height of every node's water surface for the body's origin at height originY
    /// (-inf for a sealed or empty node): the inside heads of the exchange pass.
    void nodeSurfaces(double originY, const Mat3& R, std::vector<double>& out) const {
        out.assign(nodes_.size(), -std::numeric_limits<double>::infinity());
        for (std::size_t i = 0; i < nodes_.size(); ++i) {
            if (nodes_[i].sealed || nodes_[i].water <= 0) continue;
            out[i] = originY + level(i, R);
        }
    }

    /// Applies an exchange pass's rates over dt: every node stays in [0, capacity], a full
    /// node passes what still pushes in on to the nodes it reaches through full nodes (as far
    /// as the outside surface reaches), and the amounts actually moved are booked.
    bool applyExchange(double originY, const Mat3& R, double dt, const double* inflow,
                       const double* outflow, const double* outsideTop) {
        const std::size_t n = nodes_.size();
        levels_.resize(n);
        for (std::size_t i = 0; i < n; ++i) levels_[i] = memoLevel(i, R);
        bool moved = false;
        for (std::size_t i = 0; i < n; ++i) {
            GraphNodeState& node = nodes_[i];
            double gain = inflow[i] * dt, loss = outflow[i] * dt;
            if (gain == 0 && loss == 0) continue;
            // Water entering a flooded stern compartment goes on into the holds.
            double excess = node.water + gain - loss - node.capacity;
            while (excess > 0) {
                const Path path =
                    findPath(static_cast<int>(i), R, levels_, outsideTop[i] - originY);
                if (path.node < 0) break;
                GraphNodeState& target = nodes_[path.node];
                const double before = target.water;
                target.water = std::min(target.capacity, before + excess);
                const double passed = target.water - before;
                if (!(passed > 0)) break;
                excess -= passed;
                totals_.entered += passed;
                levels_[path.node] = memoLevel(path.node, R);
                moved = true;
            }
            // Limits: the node stays within [0, capacity]; what is cut is what did not move.
            if (node.water + gain - loss > node.capacity) gain = node.capacity - node.water + loss;
            if (node.water + gain - loss < 0) loss = node.water + gain;
            const double before = node.water;
            node.water = std::clamp(before + gain - loss, 0.0, node.capacity);
            // Book what the node actually changed by, split as gain and loss.
            const double change = node.water - before;
            const double booked = gain - loss;
            if (change != booked) {
                if (change > booked)
                    gain += change - booked;
                else
                    loss += booked - change;
            }
            totals_.entered += gain;
            totals_.left += loss;
            moved = moved || change != 0 || gain != 0;
        }
        return moved;
    }

    /// The paper's findDischargeNode (Algorithm 1) for node `source`: a node reachable along
    /// open pipes, with room, whose level is below the source's; the search passes only
    /// through full nodes and never through a node higher than the source. -1: none.
    int findDischargeNode(int source, const Mat3& R) {
        if (nodes_[source].water <= 0) return -1;
        std::vector<double> levels(nodes_.size());
        for (std::size_t i = 0; i < levels.size(); ++i) levels[i] = level(i, R);
        return findPath(source, R, levels, levels[source]).node;
    }

    /// Flow between nodes over dt (Poiseuille along the downhill path, or diffusion).
    bool flowInside(const Mat3& R, double dt, const GraphSettings& s) {
        return s.flow == FlowMode::Diffusion ? flowDiffusion(dt, s) : flowPoiseuille(R, dt, s);
    }

    /// Where node i's water sits (object space): its position, or with the free-surface model
    /// the centroid of the water at its lowest side along gravity.
    Vec3 waterCentroid(std::size_t node, double water, const Mat3& R,
                       const GraphSettings& s) const {
        const GraphNodeState& n = nodes_[node];
        if (!s.freeSurface || water >= n.capacity) return n.position;
        if (!n.isBox()) {
            // Sphere cap of height h: centroid 3 (2R - h)^2 / (4 (3R - h)) below the centre.
            const double r = radius_[node];
            const double offset =
                water == n.water ? currentOffset(node, R) : levelOffset(node, water, R);
            const double h = std::clamp(offset + r, 0.0, 2.0 * r);
            const double below =
                h > 0 ? 3.0 * (2.0 * r - h) * (2.0 * r - h) / (4.0 * (3.0 * r - h)) : r;
            return n.position - below * R.row(1);
        }
        const NodeVolume volume(*this, node, R);
        const double offset = water == n.water && memoHolds(R) && memo_[node].water == water
                                  ? memo_[node].offset
                                  : levelOffset(volume, node, water, R);
        const ClippedVolume c = volume.clip(offset);
        if (!(c.volume > 0) || !std::isfinite(c.volume)) return n.position;
        const Vec3 centroid{0.0 + c.moment.x / c.volume, 0.0 + c.moment.y / c.volume,
                            0.0 + c.moment.z / c.volume};
        return n.position + transposeTimes(R, centroid);
    }

    /// The water's mass properties (paper eqs. 15-17: point masses rho v at waterCentroid).
    WaterMass waterMass(const Mat3& R, const GraphSettings& s) const {
        WaterMass p;
        Vec3 moment;
        // The point masses: on the stack for up to kLocal wet nodes (no allocation a step).
        constexpr std::size_t kLocal = 32;
        std::pair<double, Vec3> local[kLocal];
        std::vector<std::pair<double, Vec3>> spill;
        std::size_t count = 0;
        for (std::size_t i = 0; i < nodes_.size(); ++i) {
            const double w = nodes_[i].water;
            if (!(w > 0)) continue;
            const double m = s.density * w;
            const Vec3 c = waterCentroid(i, w, R, s);
            if (count < kLocal)
                local[count] = {m, c};
            else
                spill.emplace_back(m, c);
            ++count;
            p.mass += m;
            p.volume += w;
            moment += m * c;
        }
        if (!(p.mass > 0)) return p;
        p.centerOfMass = {moment.x / p.mass, moment.y / p.mass, moment.z / p.mass};
        for (std::size_t j = 0; j < count; ++j) {  // about the centre of mass (parallel axes)
            const std::pair<double, Vec3>& point = j < kLocal ? local[j] : spill[j - kLocal];
            const double m = point.first;
            const Vec3 d = point.second - p.centerOfMass;
            const double dv[3] = {d.x, d.y, d.z};
            const double squared = dot(d, d);
            for (int r = 0; r < 3; ++r) {
                for (int k = 0; k < 3; ++k) {
                    p.inertia[r][k] += m * ((r == k ? squared : 0.0) - dv[r] * dv[k]);
                }
            }
        }
        return p;
    }

private:
    struct Link {
        std::uint32_t node, pipe;
    };
    /// A frame of findPath's search: its node's shuffled neighbours order[begin, end), the
    /// next to try, and the narrowest pipe and the length on the way to it.
    struct PathFrame {
        std::size_t begin, next, end;
        double radius, length;
    };
    struct Path {
        int node = -1;
        double radius = 0;  ///< narrowest pipe on the way, m
        double length = 0;  ///< along the way, m
    };

    double levelOffset(const NodeVolume& volume, std::size_t node, double water,
                       const Mat3& R) const {
        const auto [lo, hi] = levelRange(node, R);
        if (water <= 0) return lo;
        const double capacity = nodes_[node].capacity;
        if (water >= capacity) return hi;
        // The ends' volumes are 0 and the capacity (clamped there).
        const RootBracket b = bracketRoot([&](double x) { return volume(x) - water; }, lo, hi,
                                          -water, capacity - water, levelTolerance);
        return 0.5 * (b.lo + b.hi);
    }

    /// The level search's memo: per node, the water it was made for and the offset found, at
    /// the rotation memoR_ (a pure function of the two: restoring, copying or setting water
    /// changes nothing it would give).
    struct LevelMemo {
        double water = std::numeric_limits<double>::quiet_NaN();  ///< NaN: none
        double offset = 0;
    };
    bool memoHolds(const Mat3& R) const {
        if (memo_.size() != nodes_.size()) return false;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (!(memoR_.m[i][j] == R.m[i][j])) return false;
        return true;
    }
    /// levelOffset of node i's own water at R: from the memo when it holds it.
    double currentOffset(std::size_t node, const Mat3& R) const {
        const double water = nodes_[node].water;
        if (memoHolds(R) && memo_[node].water == water) return memo_[node].offset;
        return levelOffset(node, water, R);
    }
    /// level(), keeping what it finds in the memo.
    double memoLevel(std::size_t node, const Mat3& R) {
        if (!memoHolds(R)) {
            memo_.assign(nodes_.size(), LevelMemo{});
            memoR_ = R;
        }
        LevelMemo& m = memo_[node];
        const double water = nodes_[node].water;
        if (!(m.water == water)) {
            m.offset = levelOffset(node, water, R);
            m.water = water;
        }
        return nodeHeight(node, R) + m.offset;
    }

    std::uint64_t random() {
        // splitmix64: the same sequence on every platform and standard library.
        std::uint64_t z = (rng_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    std::uint64_t randomBelow(std::uint64_t n) { return random() % n; }

    /// Algorithm 1 with an explicit stack (deep graphs cannot overflow). sourceLevel: the
    /// height the water comes from (the source's level, or the outside surface pushing
    /// through a full node), relative to the body's origin.
    Path findPath(int source, const Mat3& R, const std::vector<double>& levels,
                  double sourceLevel) {
        Path none;
        if (nodes_[source].sealed) return none;
        // Visited marks by epoch: no O(nodes) clear per search (a Poiseuille step searches
        // from every node, which made it quadratic in the node count).
        if (visitMark_.size() != nodes_.size() || ++visitEpoch_ == 0) {
            visitMark_.assign(nodes_.size(), 0);
            visitEpoch_ = 1;
        }
        visitMark_[source] = visitEpoch_;
        // Each frame's neighbours, shuffled, in one buffer (a frame's run ends where the next
        // frame's starts); the buffer and the stack are kept between searches.
        std::vector<Link>& order = pathOrder_;
        std::vector<PathFrame>& stack = pathStack_;
        order.clear();
        stack.clear();
        auto push = [&](int node, double radius, double length) {
            const std::size_t begin = order.size();
            order.insert(order.end(), links_[node].begin(), links_[node].end());
            Link* run = order.data() + begin;
            for (std::size_t i = order.size() - begin; i > 1; --i)
                std::swap(run[i - 1], run[randomBelow(i)]);
            stack.push_back({begin, begin, order.size(), radius, length});
        };
        push(source, std::numeric_limits<double>::infinity(), 0.0);
        while (!stack.empty()) {
            PathFrame& top = stack.back();
            if (top.next == top.end) {
                order.resize(top.begin);  // the last run in the buffer
                stack.pop_back();
                continue;
            }
            const Link link = order[top.next++];
            const int m = static_cast<int>(link.node);
            if (visitMark_[m] == visitEpoch_) continue;
            visitMark_[m] = visitEpoch_;
            // A node whose lowest point lies above the source's level is an energy barrier.
            if (nodeHeight(m, R) + levelRange(m, R).first > sourceLevel) continue;
            const double radius = std::min(top.radius, pipes_[link.pipe].radius);
            const double length = top.length + length_[link.pipe];
            const GraphNodeState& node = nodes_[m];
            const bool full = node.water >= node.capacity;
            if (!full && levels[m] < sourceLevel) return {m, radius, length};
            // Water passes on only through a full node (paper figure 7: A through B to C).
            if (full) push(m, radius, length);
        }
        return none;
    }

    /// Every node in random order sends Q dt (Q = pi rho g dh r^4 / (8 mu L)) to its discharge
    /// node, at most what brings both levels together, so that nothing oscillates.
    bool flowPoiseuille(const Mat3& R, double dt, const GraphSettings& s) {
        const std::size_t n = nodes_.size();
        std::vector<double>& levels = flowLevels_;
        levels.resize(n);
        for (std::size_t i = 0; i < n; ++i) levels[i] = memoLevel(i, R);
        std::vector<std::size_t>& order = order_;
        order.resize(n);
        for (std::size_t i = 0; i < n; ++i) order[i] = i;
        for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[randomBelow(i)]);
        const double rhoG = s.density * s.gravity;
        bool moved = false;
        for (std::size_t source : order) {
            if (nodes_[source].water <= 0) continue;
            const Path path = findPath(static_cast<int>(source), R, levels, levels[source]);
            if (path.node < 0) continue;
            const auto d = static_cast<std::size_t>(path.node);
            GraphNodeState& a = nodes_[source];
            GraphNodeState& b = nodes_[d];
            const double dh = levels[source] - levels[d];
            const double rate =
                poiseuilleRate(rhoG * dh, path.radius, s.viscosity, std::max(path.length, 1e-9));
            // The common level L with vol_a(L) + vol_b(L) = water_a + water_b (bracketRoot; the
            // bracket's upper end keeps the move on the safe side).
            const double ha = nodeHeight(source, R), hb = nodeHeight(d, R);
            const double total = a.water + b.water;
            const NodeVolume va(*this, source, R), vb(*this, d, R);
            auto excess = [&](double L) { return (va(L - ha) + vb(L - hb)) - total; };
            const double lo = levels[d];
            double hi = levels[source];
            const double fLo = excess(lo);
            if (!(fLo < 0.0)) {
                hi = lo;  // the sum reaches the total at the lower level already
            } else if (const double fHi = excess(hi); !(fHi < 0.0)) {
                hi = bracketRoot(excess, lo, hi, fLo, fHi, [](double x) {
                         return 1e-13 * (1.0 + std::abs(x));
                     }).hi;
            }
            const double equalise = std::max(0.0, a.water - va(hi - ha));
            double amount = std::min({rate * dt, equalise, a.water, b.capacity - b.water});
            if (!(amount > 0)) continue;
            const double before = b.water;
            b.water = std::min(b.capacity, b.water + amount);
            amount = b.water - before;
            a.water = std::max(0.0, a.water - amount);
            totals_.moved += amount;
            levels[source] = memoLevel(source, R);
            levels[d] = memoLevel(d, R);
            moved = true;
        }
        return moved;
    }

    /// Along every open pipe, in random order, from the fuller node (water / capacity) to the
    /// emptier, at most until both are equally full.
    bool flowDiffusion(double dt, const GraphSettings& s) {
        const std::size_t count = pipes_.size();
        std::vector<std::size_t>& order = order_;
        order.resize(count);
        for (std::size_t i = 0; i < count; ++i) order[i] = i;
        for (std::size_t i = count; i > 1; --i) std::swap(order[i - 1], order[randomBelow(i)]);
        bool moved = false;
        for (std::size_t p : order) {
            const GraphPipeState& pipe = pipes_[p];
            if (!pipe.open) continue;
            if (nodes_[pipe.a].sealed || nodes_[pipe.b].sealed) continue;
            GraphNodeState* full = &nodes_[pipe.a];
            GraphNodeState* empty = &nodes_[pipe.b];
            double ca = full->water / full->capacity, cb = empty->water / empty->capacity;
            if (ca < cb) {
                std::swap(full, empty);
                std::swap(ca, cb);
            }
            if (!(ca > cb)) continue;
            const double rate = poiseuilleRate(s.diffusionPressure * (ca - cb), pipe.radius,
                                               s.viscosity, std::max(length_[p], 1e-9));
            const double equalise = (ca - cb) / (1.0 / full->capacity + 1.0 / empty->capacity);
            double amount =
                std::min({rate * dt, equalise, full->water, empty->capacity - empty->water});
            if (!(amount > 0)) continue;
            const double before = empty->water;
            empty->water = std::min(empty->capacity, empty->water + amount);
            amount = empty->water - before;
            full->water = std::max(0.0, full->water - amount);
            totals_.moved += amount;
            moved = true;
        }
        return moved;
    }

    std::vector<GraphNodeState> nodes_;
    std::vector<GraphPipeState> pipes_;
    std::vector<double> length_;            ///< per pipe, m (resolved)
    std::vector<std::vector<Link>> links_;  ///< open pipes per node
    std::vector<double> radius_;            ///< sphere radius per node, m
    std::vector<Vec3> scaledBox_;           ///< box nodes' edges scaled to the capacity
    std::vector<double> levels_;            ///< per node, reused by applyExchange
    std::vector<double> flowLevels_;        ///< per node, reused by flowPoiseuille
    std::vector<std::size_t> order_;        ///< random visiting order, reused by the flows
    std::vector<std::uint32_t> visitMark_;  ///< findPath's visited marks (== visitEpoch_)
    std::vector<Link> pathOrder_;           ///< findPath's shuffled neighbours, reused
    std::vector<PathFrame> pathStack_;      ///< findPath's stack, reused
    std::vector<LevelMemo> memo_;           ///< levels found at memoR_ (memoLevel)
    Mat3 memoR_;
    std::uint32_t visitEpoch_ = 0;
    GraphFlowTotals totals_;
    std::uint64_t rng_ = 1;
};

}  // namespace plimsoll_eval
