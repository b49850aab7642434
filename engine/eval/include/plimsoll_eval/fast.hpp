// The fast CPU evaluation of a body's buoyancy, pressure and drag: the same sums as entry.hpp,
// with a cost that follows the waterline rather than the surface.
//
// The entries are grouped into tiles that are compact in object space (consecutive runs of
// the entries sorted along a Morton curve). Each node (group, tile, leaf) keeps a bounding box
// and sphere, the spread of its normals and the moments of its area vectors b about the
// body's centre c (FastMoments, FastBody::centerMoments),
//   N0 = sum b,  N1 = sum b q^T,  N2 = sum b q q,  N3 = sum b q q q,
// q = p - c the entry's position about c, so that per frame a node is one of:
//   dry        every entry above the water by more than its half extent: it adds nothing;
//   submerged  every entry fully wet under a water plane: the hydrostatic sums are
//              polynomials of degree two in q (volume, pressure force and torque, moments) and
//              the drag sum one of degree three when the sign of A.v is the same over the node
//              (normal cone against the velocity spread), so they come from the moments;
//   waterline  anything else: its children decide; a leaf's entries are evaluated one by one
//              (entryTerms, in single precision).
// On waves the water is sampled once per call on a small grid over the body's footprint
// (one batched height query); each node takes the quadratic through its nearest 3 x 3
// stencil, so curved water costs no per-entry work under it either: the submerged nodes of
// one stencil add their moments, evaluated once under that quadratic about the stencil's
// point (depthIntegrals). A waterline tile gives all its
// entries its quadratic's heights. The water's own velocity (drag) is taken at a tile's centre,
// asked for in one batch after the traversal.
// Closed forms are linear in the moments, so nodes that share one polynomial add their moments
// and the polynomial is evaluated once: every submerged node under a flat plane, every
// submerged node of one stencil on waves, every facing node of one water velocity for drag
// (docs/fast-path.md).
#pragma once

#include "plimsoll_eval/entry.hpp"
#include "plimsoll_eval/vec.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <string_view>
#include <type_traits>
#include <vector>

// The evaluation is compiled twice: for the target's baseline and, on x86-64 with GCC or Clang,
// for AVX2 (a function attribute that inlines everything the evaluation calls, so that nothing
// outside it is built for AVX2), and the second runs where the processor has it
// (cpuHasAvx2Fma). Without fused multiply-adds the two give the same bits: the lanes of every
// sum are explicit and no operation is reassociated, so only the vector width differs
// (tests/runtime/test_runtime_determinism.cpp compares them). PLIMSOLL_EVAL_FMA builds the
// AVX2 variant with FMA too, whose products round once: faster where it pays, and no longer
// the baseline's bits.
#if (defined(__x86_64__) || defined(_M_X64)) && (defined(__GNUC__) || defined(__clang__))
#define PLIMSOLL_EVAL_AVX2_LOOPS 1
#ifdef PLIMSOLL_EVAL_FMA
#define PLIMSOLL_EVAL_AVX2_TARGET __attribute__((target("avx2,fma"), flatten))
#else
#define PLIMSOLL_EVAL_AVX2_TARGET __attribute__((target("avx2"), flatten))
#endif
#endif

namespace plimsoll_eval {

/// Whether the AVX2 builds of the evaluation run (checked once): where the processor has AVX2
/// and FMA, unless the environment variable PLIMSOLL_ISA is "baseline" (the instruction-set
/// switch the determinism tests and docs/c-abi.md use).
inline bool cpuHasAvx2Fma() {
#ifdef PLIMSOLL_EVAL_AVX2_LOOPS
    static const bool has = [] {
        const char* forced = std::getenv("PLIMSOLL_ISA");
        if (forced && std::string_view(forced) == "baseline") return false;
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    }();
    return has;
#else
    return false;
#endif
}

struct FastOptions {
    std::size_t tileSize = 32;  ///< entries per tile (rounded up to a power of two, 8 to 64)
    int waveGrid = 9;           ///< water samples per side of the footprint grid (>= 3)
};

/// The water as the fast path sees it: flat at `level` when `heights` is null.
struct WaterSurface {
    double level = 0;
    double minHeight = 0, maxHeight = 0;  ///< bounds of the surface (whole-body culling)
    const void* context = nullptr;
    /// n heights f(x[i], z[i], time) into out[i].
    void (*heights)(const void* context, std::size_t n, const double* x, const double* z,
                    double time, double* out) = nullptr;
    /// The water's own velocity at a point; null: still water (unless `velocities` is set).
    Vec3 (*velocity)(const void* context, const Vec3& point, double time) = nullptr;
    /// The same at n points in one call (out[3 i + 0..2] for point i): game engines' water
    /// queries are batched and costly, and a batch vectorises. Preferred over `velocity`.
    void (*velocities)(const void* context, std::size_t n, const double* x, const double* y,
                       const double* z, double time, double* out) = nullptr;

    bool moving() const { return velocity != nullptr || velocities != nullptr; }

    static WaterSurface flat(double level) {
        WaterSurface w;
        w.level = w.minHeight = w.maxHeight = level;
        return w;
    }
};

/// One body for one evaluation. `center` is the body's centre c in world coordinates (the
/// point its entries were given relative to), `linear` the velocity of c.
struct BodyState {
    Mat3 rotation;
    Vec3 center;
    Vec3 linear;
    Vec3 angular;
    double time = 0;
};

/// How the tiles of the last evaluation were treated (for the benchmark and tests).
struct FastStats {
    std::size_t dry = 0, closedForm = 0, perEntry = 0, waterSamples = 0;
    std::size_t dragPerEntry = 0;     ///< leaves of submerged nodes whose drag alone is per entry
    std::size_t velocitySamples = 0;  ///< points of the water-velocity batch
};

/// What the traversal reads at every node it visits (the moments, read only where a node is
/// summed in closed form, live apart in FastMoments: a thousand bodies' nodes then stay in cache).
struct FastTile {
    std::uint32_t begin = 0, end = 0;
    std::uint32_t firstChild = 0, children = 0;  ///< sub-tiles of kLanes entries (top tiles)
    Vec3 center;                                 ///< object space, relative to c
    Vec3 halfSize;                               ///< of the box of the entry positions about center
    double radius = 0;                           ///< of the entry positions about center
    double halfExtent = 0;                       ///< half the largest entry's side sqrt(area)
    Vec3 axis;                                   ///< mean normal direction
    double cosSpread = -1;  ///< cosine of the largest angle of a normal from axis
    double areaSum = 0;
    double count = 0;  ///< entries (padding left out)
};

/// Slot of the symmetric index pair (j, l) and triple (j, l, m) in FastMoments' packed arrays.
inline constexpr int kPair[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
/// The index pair of each of kPair's slots.
inline constexpr int kPairFirst[6] = {0, 0, 0, 1, 1, 2};
inline constexpr int kPairSecond[6] = {0, 1, 2, 1, 2, 2};
inline constexpr int kTriple[3][3][3] = {{{0, 1, 2}, {1, 3, 4}, {2, 4, 5}},
                                         {{1, 3, 4}, {3, 6, 7}, {4, 7, 8}},
                                         {{2, 4, 5}, {4, 7, 8}, {5, 8, 9}}};

/// Moments of area vectors b about a point (s their positions from it, object axes): n0 =
/// sum b, n1 = sum b s^T, n2 = sum b s s, n3 = sum b s s s, the last two symmetric in the s
/// indices and stored once per index set (kPair, kTriple). A node's are about the body's
/// centre c (on waves a stencil's sum is evaluated about the stencil's point: depthIntegrals).
struct FastMoments {
    double n0[3] = {};
    double n1[3][3] = {};
    double n2[3][6] = {};
    double n3[3][10] = {};

    /// Becomes the sum of the moments `terms[0..count)` point to (orders 0 to `order`; higher
    /// ones are left as they were), all taken about the same point. Member by member, each an
    /// outer loop over the terms, so that its running sum stays in registers and every term is
    /// read once (adding them two at a time into memory read and wrote the sum once a term).
    void setSum(const FastMoments* const* terms, std::size_t count, int order = 3) {
        sumOf(
            terms, count, [](const FastMoments& m) -> const auto& { return m.n0; }, n0);
        sumOf(
            terms, count, [](const FastMoments& m) -> const auto& { return m.n1; }, n1);
        sumOf(
            terms, count, [](const FastMoments& m) -> const auto& { return m.n2; }, n2);
        if (order >= 3)
            sumOf(
                terms, count, [](const FastMoments& m) -> const auto& { return m.n3; }, n3);
    }

private:
    template <class Member, std::size_t Rows, std::size_t Columns>
    static void sumOf(const FastMoments* const* terms, std::size_t count, Member member,
                      double (&out)[Rows][Columns]) {
        double sum[Rows * Columns];
        const auto& first = member(*terms[0]);
        for (std::size_t r = 0; r < Rows; ++r)
            for (std::size_t c = 0; c < Columns; ++c) sum[r * Columns + c] = first[r][c];
        for (std::size_t t = 1; t < count; ++t) {
            const auto& next = member(*terms[t]);
            for (std::size_t r = 0; r < Rows; ++r)
                for (std::size_t c = 0; c < Columns; ++c) sum[r * Columns + c] += next[r][c];
        }
        for (std::size_t r = 0; r < Rows; ++r)
            for (std::size_t c = 0; c < Columns; ++c) out[r][c] = sum[r * Columns + c];
    }
    template <class Member, std::size_t Rows>
    static void sumOf(const FastMoments* const* terms, std::size_t count, Member member,
                      double (&out)[Rows]) {
        double sum[Rows];
        for (std::size_t r = 0; r < Rows; ++r) sum[r] = member(*terms[0])[r];
        for (std::size_t t = 1; t < count; ++t)
            for (std::size_t r = 0; r < Rows; ++r) sum[r] += member(*terms[t])[r];
        for (std::size_t r = 0; r < Rows; ++r) out[r] = sum[r];
    }
};

/// A sum of nodes' moments formed when it is read, in one pass over its terms (setSum), and only
/// where it has two: while a bucket holds one node it reads that node's moments in place. On
/// waves nearly every drag bucket holds one node (each wet tile has its own water velocity) and
/// a stencil's a few, and zeroing and adding 480 bytes a node cost more than its closed form. The
/// moments added must outlive the sum (a body's centerMoments do, for the call); the list of
/// terms keeps its capacity from call to call.
class FastMomentSum {
public:
    void clear() { terms_.clear(); }
    void add(const FastMoments& m) { terms_.push_back(&m); }
    /// The sum, orders 0 to `order` (the higher ones only meaningful where every term has them).
    const FastMoments& moments(int order = 3) {
        static const FastMoments none;
        if (terms_.empty()) return none;
        if (terms_.size() == 1) return *terms_[0];
        sum_.setSum(terms_.data(), terms_.size(), order);
        return sum_;
    }

private:
    FastMoments sum_;
    std::vector<const FastMoments*> terms_;
};

/// The next of a call's buckets in `pool`, whose first `used` are taken: entries are reused
/// from call to call (not cleared), so the caller sets every field; the pool grows only on the
/// first calls.
template <class Bucket>
inline Bucket& nextBucket(std::vector<Bucket>& pool, std::size_t& used) {
    if (pool.size() <= used) pool.emplace_back();
    return pool[used++];
}

/// Consecutive leaves of kLanes entries (a tile's, or one leaf) left to per-entry work, with
/// their water in single precision: the surface's quadratic f + g.d + d^T H d / 2 (hxx, hzz
/// halved) about (cx, cz) relative to c, and the body's velocity relative to the water there
/// (in the body's axes, as the per-entry loops work: FloatRotation).
/// One record a tile rather than one a leaf: its leaves share the tile's water.
struct FastLeafWork {
    std::uint32_t begin = 0;
    std::uint32_t leaves = 1;
    float cx = 0, cz = 0, f = 0, gx = 0, gz = 0, hxx = 0, hxz = 0, hzz = 0;
    float ux = 0, uy = 0, uz = 0;
    /// The point of the call's velocity batch the relative velocity is taken at (-1: still
    /// water); u is filled in after the batch.
    std::int32_t slot = -1;
    /// An entry this far above the water (or more) adds nothing: half the largest entry's side,
    /// with a margin for rounding (perEntryLeaves skips leaves whose entries all are).
    float dryAbove = 0;
};

/// A submerged node whose drag waits for the water's velocity (one batched query per call).
struct FastDeferredDrag {
    std::uint32_t node = 0;
    std::int32_t slot = -1;  ///< its point in FastScratch's velocity batch; -1: still water
};

/// What the hydrostatic sums need of wholly wet entries under a water quadratic: with the depth
/// (object axes) d(s) = alpha + beta.s + s^T H s / 2 about a point p (s = q - p),
///   d0 = sum d b,   d1 = sum d b q^T (about c),   e = sum d^2 b less sum (s^T H s)^2 b / 4,
/// the one term the moments do not reach (fourth order; of the order of the curvature's squared
/// departure over the entries, smallest about a point among them: FastBody::evaluate takes p
/// above the stencil's grid node at the mean height of its nodes' centres).
struct FastDepthIntegrals {
    double d0[3] = {};
    double d1[3][3] = {};
    double e[3] = {};
};

/// The water's Hessian in object axes, R^T H3 R, H3 the horizontal Hessian (hxx, hxz, hzz) in
/// world axes: its y row and column are zero, so only the x and z rows of R enter.
inline void objectHessian(const Mat3& R, double hxx, double hxz, double hzz, double H[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            H[i][j] = R.m[0][i] * hxx * R.m[0][j] + R.m[0][i] * hxz * R.m[2][j] +
                      R.m[2][i] * hxz * R.m[0][j] + R.m[2][i] * hzz * R.m[2][j];
}

/// The depth integrals of entries whose moments about c are m (orders 0 to 2, and 3 where H is
/// not zero). d0 and d1 take the depth expanded about c, where it is the same quadratic with
///   alpha' = alpha - beta.p + p^T H p / 2,   beta' = beta - H p,
/// so that they are exact in the moments about c without shifting them. e is taken about p (its
/// left-out term is smallest there), its moments about p written through those about c:
///   e = alpha^2 n0 + 2 alpha (n1 beta)' + (beta n2 beta)' + alpha (n2:H)' + (beta.(n3:H))'
///   (n1 beta)'      = n1 beta - n0 (p.beta)
///   (beta n2 beta)' = beta n2 beta - 2 (n1 beta)(p.beta) + n0 (p.beta)^2
///   (n2:H)'         = n2:H - 2 n1 Hp + n0 pHp
///   (beta.(n3:H))'  = beta.(n3:H) - 2 beta.(n2 Hp) - (p.beta)(n2:H) + (n1 beta) pHp
///                     + 2 (p.beta)(n1 Hp) - n0 (p.beta) pHp
/// (the contraction with beta of n3 shifted by p, its terms the binomial expansion of
/// (s + p)(s + p)(s + p) against H). One pass over the moments: what a stencil's bucket costs.
inline FastDepthIntegrals depthIntegrals(const FastMoments& m, const Vec3& p, double alpha,
                                         const Vec3& beta, const double H[3][3]) {
    bool curved = false;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) curved = curved || H[i][j] != 0;
    const double pv[3] = {p.x, p.y, p.z}, bv[3] = {beta.x, beta.y, beta.z};
    double Hp[3] = {}, pHp = 0;
    // H packed as kPair's slots, its off-diagonal terms doubled: n:H over 6 slots, not 9.
    double Hs[6] = {};
    if (curved) {
        for (int l = 0; l < 3; ++l) Hp[l] = H[l][0] * pv[0] + H[l][1] * pv[1] + H[l][2] * pv[2];
        pHp = pv[0] * Hp[0] + pv[1] * Hp[1] + pv[2] * Hp[2];
        for (int j = 0; j < 3; ++j)
            for (int l = j; l < 3; ++l) Hs[kPair[j][l]] = (j == l ? 1.0 : 2.0) * H[j][l];
    }
    const double pb = pv[0] * bv[0] + pv[1] * bv[1] + pv[2] * bv[2];
    const double alphaC = alpha - pb + 0.5 * pHp;
    FastDepthIntegrals out;
    for (int u = 0; u < 3; ++u) {
        const double n0 = m.n0[u];
        double n1b = 0, n1Hp = 0, n2H = 0, n2bb = 0, n2bHp = 0, bn3H = 0;
        double n2b[3], n2Hp[3] = {}, n3H[3] = {};
        for (int j = 0; j < 3; ++j) {
            n1b += m.n1[u][j] * bv[j];
            n2b[j] = m.n2[u][kPair[j][0]] * bv[0] + m.n2[u][kPair[j][1]] * bv[1] +
                     m.n2[u][kPair[j][2]] * bv[2];
            n2bb += n2b[j] * bv[j];
        }
        if (curved) {
            for (int j = 0; j < 3; ++j) {
                n1Hp += m.n1[u][j] * Hp[j];
                n2Hp[j] = m.n2[u][kPair[j][0]] * Hp[0] + m.n2[u][kPair[j][1]] * Hp[1] +
                          m.n2[u][kPair[j][2]] * Hp[2];
                n2bHp += bv[j] * n2Hp[j];
                double c = 0;
                for (int l = 0; l < 6; ++l)
                    c += m.n3[u][kTriple[j][kPairFirst[l]][kPairSecond[l]]] * Hs[l];
                n3H[j] = c;
                bn3H += bv[j] * c;
            }
            for (int l = 0; l < 6; ++l) n2H += m.n2[u][l] * Hs[l];
        }
        out.d0[u] = alphaC * n0 + n1b - n1Hp + 0.5 * n2H;
        for (int j = 0; j < 3; ++j)
            out.d1[u][j] = alphaC * m.n1[u][j] + n2b[j] - n2Hp[j] + 0.5 * n3H[j];
        const double n1bP = n1b - n0 * pb;
        const double n2bbP = n2bb - 2 * n1b * pb + n0 * pb * pb;
        const double n2HP = n2H - 2 * n1Hp + n0 * pHp;
        const double bn3HP =
            bn3H - 2 * n2bHp - pb * n2H + n1b * pHp + 2 * pb * n1Hp - n0 * pb * pHp;
        out.e[u] = alpha * alpha * n0 + 2 * alpha * n1bP + n2bbP + alpha * n2HP + bn3HP;
    }
    return out;
}

/// Closed-form work summed over many nodes before it is evaluated once: their moments about
/// the body's centre c add up, and a polynomial in q evaluated on the sum is the sum of its
/// values. This one holds the drag of the nodes that share one water velocity (a slot); the
/// hydrostatics under a flat plane are FastScratch::flatHydrostatics, those of a wave stencil
/// a FastStencilBucket.
struct FastBucket {
    FastMomentSum moments;
    std::int32_t slot = -1;
};

/// The water's quadratic through the 3 x 3 grid points about one grid node (heights relative to
/// c.y): f + g.d + d^T H d / 2, d the horizontal offset from the node.
struct FastStencil {
    double f = 0, gx = 0, gz = 0, hxx = 0, hxz = 0, hzz = 0;
    double frobenius = 0;  ///< |H|_F
};

/// Waves: the submerged nodes of one grid node's stencil (they share its quadratic), with the
/// sum of their centres' heights weighed by their entries, for the point they are expanded about.
struct FastStencilBucket {
    FastMomentSum moments;
    int node = 0;  ///< j * G + i
    double heightSum = 0, entries = 0;
};

struct FastScratch {
    std::vector<double> x, z, h;
    std::vector<FastStencil> stencilQuadratics;  ///< per grid node (inner nodes only)
    std::vector<FastLeafWork> leaves;
    std::vector<FastLeafWork>
        dragLeaves;  ///< wholly wet: only the entries and the velocity are set
    std::vector<FastDeferredDrag> drags;
    /// The velocity batch: its points, then 3 per point, the water's velocity there as the batch
    /// gives it and, once read, the body's velocity relative to it in the body's axes.
    std::vector<double> px, py, pz, velocity;
    FastMomentSum flatHydrostatics;  ///< flat water: every submerged node's moments
    /// Waves: submerged nodes' moments per grid node; the first `stencilCount` are this call's
    /// (entries are reused, not cleared, from call to call).
    std::vector<FastStencilBucket> stencils;
    std::size_t stencilCount = 0;
    std::vector<std::int32_t> stencilBucket;  ///< index into stencils by grid node; -1: none
    /// One per velocity slot in use: the first `dragBucketCount` (reused as `stencils`).
    std::vector<FastBucket> dragBuckets;
    std::size_t dragBucketCount = 0;
    std::vector<std::int32_t> bucketOfSlot;  ///< index into dragBuckets by slot + 1; -1: none
};

/// A body's entries in tile order (single precision, structure of arrays) and its tiles.
class FastBody {
public:
    /// `entry(i, p, a, area)` fills entry i's position and area vector (object space) and area;
    /// `center` is the body's centre c.
    template <class Entry>
    void build(std::size_t count, Entry entry, const Vec3& center,
               const FastOptions& options = {}) {
        options_ = options;
        center_ = center;
        std::vector<Vec3> p(count), a(count);
        std::vector<double> area(count);
        Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
        for (std::size_t i = 0; i < count; ++i) {
            entry(i, p[i], a[i], area[i]);
            p[i] -= center;
            lo = {std::min(lo.x, p[i].x), std::min(lo.y, p[i].y), std::min(lo.z, p[i].z)};
            hi = {std::max(hi.x, p[i].x), std::max(hi.y, p[i].y), std::max(hi.z, p[i].z)};
        }
        // Morton order: tiles of consecutive entries are then compact in object space.
        const double span = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-30});
        std::vector<std::uint64_t> key(count);
        for (std::size_t i = 0; i < count; ++i) {
            auto cell = [&](double v, double l) {
                return static_cast<std::uint64_t>(std::clamp((v - l) / span, 0.0, 1.0) * 1023.0);
            };
            key[i] = interleave(cell(p[i].x, lo.x)) | interleave(cell(p[i].y, lo.y)) << 1 |
                     interleave(cell(p[i].z, lo.z)) << 2;
        }
        std::vector<std::uint32_t> order(count);
        std::iota(order.begin(), order.end(), 0u);
        std::stable_sort(order.begin(), order.end(),
                         [&](std::uint32_t u, std::uint32_t v) { return key[u] < key[v]; });
        // Tiles of a power of two of entries, the last padded with entries that weigh nothing
        // (valid 0, zero area).
        std::size_t size = kLanes;
        while (size < std::min(options.tileSize, kMaxTile)) size *= 2;
        const std::size_t padded = (count + size - 1) / size * size;
        for (auto* column : {&qx_, &qy_, &qz_, &bx_, &by_, &bz_, &area_, &inverseLength2_,
                             &inverseLength_, &valid_})
            column->assign(padded, 0.0f);
        for (std::size_t i = 0; i < count; ++i) {
            const std::uint32_t k = order[i];
            qx_[i] = static_cast<float>(p[k].x);
            qy_[i] = static_cast<float>(p[k].y);
            qz_[i] = static_cast<float>(p[k].z);
            bx_[i] = static_cast<float>(a[k].x);
            by_[i] = static_cast<float>(a[k].y);
            bz_[i] = static_cast<float>(a[k].z);
            area_[i] = static_cast<float>(area[k]);
            const float length2 = bx_[i] * bx_[i] + by_[i] * by_[i] + bz_[i] * bz_[i];
            inverseLength2_[i] = length2 > 0 ? 1.0f / length2 : 0.0f;
            inverseLength_[i] = 1.0f / std::max(std::sqrt(length2), 1e-30f);
            valid_[i] = 1.0f;
        }
        // Three levels, all compact in object space along the Morton order: groups of
        // kGroupTiles tiles, tiles of `size` entries, leaves of kLanes entries. A node that is
        // neither dry nor summable in closed form is looked at again in its children; only
        // leaves are evaluated per entry.
        std::vector<FastTile> groups, tiles, leaves;
        for (std::size_t begin = 0; begin < padded; begin += size * kGroupTiles) {
            FastTile g = makeTile(begin, std::min(padded, begin + size * kGroupTiles));
            g.firstChild = static_cast<std::uint32_t>(tiles.size());
            for (std::size_t t0 = g.begin; t0 < g.end; t0 += size) {
                FastTile t = makeTile(t0, t0 + size);
                t.firstChild = static_cast<std::uint32_t>(leaves.size());
                if (size > kLanes)
                    for (std::size_t sub = t0; sub < t0 + size; sub += kLanes)
                        if (valid_[sub] != 0) leaves.push_back(makeTile(sub, sub + kLanes));
                t.children = static_cast<std::uint32_t>(leaves.size()) - t.firstChild;
                tiles.push_back(t);
            }
            g.children = static_cast<std::uint32_t>(tiles.size()) - g.firstChild;
            groups.push_back(g);
        }
        roots_ = static_cast<std::uint32_t>(groups.size());
        tileCount_ = tiles.size();
        nodes_ = groups;
        for (FastTile& g : nodes_) g.firstChild += roots_;
        const std::uint32_t leafOffset = roots_ + static_cast<std::uint32_t>(tiles.size());
        for (FastTile& t : tiles) {
            if (t.children > 0) t.firstChild += leafOffset;
            nodes_.push_back(t);
        }
        nodes_.insert(nodes_.end(), leaves.begin(), leaves.end());
        centerMoments_.clear();
        sinSpread_.clear();
        for (const FastTile& t : nodes_) {
            momentsAbout(t.begin, t.end, Vec3{}, centerMoments_.emplace_back());
            sinSpread_.push_back(std::sqrt(std::max(0.0, 1.0 - t.cosSpread * t.cosSpread)));
        }
        radius_ = 0;
        for (const FastTile& t : tiles)
            radius_ = std::max(radius_, norm(t.center) + t.radius + t.halfExtent);
    }

    std::size_t size() const { return qx_.size(); }  ///< entries, padded to whole lanes
    /// Every node of the three levels (groups first; see build).
    const std::vector<FastTile>& nodes() const { return nodes_; }
    /// Their moments (same index) about the body's centre c (s = q): what buckets sum, and
    /// shift to a wave stencil's point where the depth is expanded about it.
    const std::vector<FastMoments>& centerMoments() const { return centerMoments_; }
    /// Tiles of FastOptions::tileSize entries (the middle level).
    std::size_t tileCount() const { return tileCount_; }
    const Vec3& center() const { return center_; }
    /// Largest distance of an entry (with its half extent) from c.
    double radius() const { return radius_; }
    const FastOptions& options() const { return options_; }
    /// Heap bytes the tiles hold (entries' columns, nodes, their moments).
    std::size_t memoryBytes() const {
        std::size_t bytes = 0;
        for (const auto* column : {&qx_, &qy_, &qz_, &bx_, &by_, &bz_, &area_, &inverseLength2_,
                                   &inverseLength_, &valid_})
            bytes += column->capacity() * sizeof(float);
        return bytes + nodes_.capacity() * sizeof(FastTile) +
               centerMoments_.capacity() * sizeof(FastMoments) +
               sinSpread_.capacity() * sizeof(double);
    }

    /// The body's sums about c for one state (see the file comment).
    Sums evaluate(const BodyState& state, const WaterSurface& water, const Coefficients& k,
                  FastScratch& scratch, FastStats* stats = nullptr) const;

private:
    static constexpr std::size_t kLanes = 8;     ///< partial sums per column of the per-entry sums
    static constexpr std::size_t kMaxTile = 64;  ///< entries per tile at most
    static constexpr std::size_t kGroupTiles = 8;  ///< tiles per group

    static std::uint64_t interleave(std::uint64_t v) {
        v &= 0x3ff;
        v = (v | v << 16) & 0x30000ff;
        v = (v | v << 8) & 0x300f00f;
        v = (v | v << 4) & 0x30c30c3;
        v = (v | v << 2) & 0x9249249;
        return v;
    }

    /// The moments of entries [begin, end) about `point` (object space, relative to c).
    void momentsAbout(std::size_t begin, std::size_t end, const Vec3& point,
                      FastMoments& mo) const {
        for (std::size_t i = begin; i < end; ++i) {
            if (valid_[i] == 0) continue;
            const double b[3] = {bx_[i], by_[i], bz_[i]};
            const double d[3] = {qx_[i] - point.x, qy_[i] - point.y, qz_[i] - point.z};
            for (int u = 0; u < 3; ++u) {
                mo.n0[u] += b[u];
                for (int j = 0; j < 3; ++j) {
                    mo.n1[u][j] += b[u] * d[j];
                    for (int l = j; l < 3; ++l) {
                        mo.n2[u][kPair[j][l]] += b[u] * d[j] * d[l];
                        for (int n = l; n < 3; ++n)
                            mo.n3[u][kTriple[j][l][n]] += b[u] * d[j] * d[l] * d[n];
                    }
                }
            }
        }
    }

    /// The node over entries [begin, end).
    FastTile makeTile(std::size_t begin, std::size_t end) const {
        FastTile t;
        t.begin = static_cast<std::uint32_t>(begin);
        t.end = static_cast<std::uint32_t>(end);
        Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300}, normals;
        double largest = 0;
        // Bounds of what the per-entry path sees: the single-precision entries.
        auto position = [&](std::size_t i) { return Vec3{qx_[i], qy_[i], qz_[i]}; };
        auto areaVector = [&](std::size_t i) { return Vec3{bx_[i], by_[i], bz_[i]}; };
        for (std::size_t i = begin; i < end; ++i) {
            if (valid_[i] == 0) continue;
            const Vec3 q = position(i), b = areaVector(i);
            lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
            hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
            const double length = norm(b);
            if (length > 0) normals += (1.0 / length) * b;
            largest = std::max(largest, double(area_[i]));
        }
        t.center = 0.5 * (lo + hi);
        t.halfSize = 0.5 * (hi - lo);
        t.halfExtent = 0.5 * std::sqrt(largest);
        const double axisLength = norm(normals);
        t.axis = axisLength > 0 ? (1.0 / axisLength) * normals : Vec3{0, 1, 0};
        t.cosSpread = axisLength > 0 ? 1.0 : -1.0;
        for (std::size_t i = begin; i < end; ++i) {
            if (valid_[i] == 0) continue;
            const Vec3 qv = position(i), bv = areaVector(i);
            t.radius = std::max(t.radius, norm(qv - t.center));
            const double length = norm(bv);
            if (length > 0 && axisLength > 0)
                t.cosSpread = std::min(t.cosSpread, dot(bv, t.axis) / length);
            t.areaSum += area_[i];
            t.count += 1;
        }
        // Rounding may make the widest normal or the farthest entry a hair wider than measured.
        t.cosSpread = std::max(-1.0, t.cosSpread - 1e-6);
        t.radius *= 1.0 + 1e-6;
        t.halfSize = (1.0 + 1e-6) * t.halfSize;
        return t;
    }

    /// The water over one tile: f(d) = f + g.d + d^T H d / 2 relative to c.y, d the horizontal
    /// offset from the tile's centre (world axes). (Its velocity is a slot of the call's batch.)
    struct TileWater {
        double f = 0, gx = 0, gz = 0, hxx = 0, hxz = 0, hzz = 0;
    };

    /// Whether t is a group (the top level; groups come first in nodes_).
    bool isGroup(const FastTile& t) const { return &t < nodes_.data() + roots_; }

    /// How the entries of node t meet the flow (object axes: uo the body's velocity relative to
    /// the water at c, wo its spin, spinRate = |wo|): all turned away (no pressure drag), all
    /// facing it (the drag is a polynomial of their moments), or mixed (its children decide).
    enum class DragSign { away, facing, mixed };
    DragSign dragSign(const FastTile& t, double sinSpread, const Vec3& uo, const Vec3& wo,
                      double spinRate, const Coefficients& k) const;
    /// The pressure drag of entries that all face the flow, from their moments about `center`
    /// (object axes; torque about c).
    static void dragFromMoments(const FastMoments& mo, const Vec3& center, const Vec3& uo,
                                const Vec3& wo, const Coefficients& k, Vec3& force, Vec3& torque);
    /// The hydrostatic sums of wholly wet entries from their depth integrals.
    static void hydrostaticsFromDepthIntegrals(const FastDepthIntegrals& in, const Mat3& R,
                                               const Coefficients& k, Sums& sum);
    /// The columns of the kLanes entries of one leaf.
    struct LeafColumns {
        const float *qx, *qy, *qz, *bx, *by, *bz, *area, *inverseLength2, *inverseLength, *valid;
    };
    /// Calls leaf(record, columns) for every leaf of every record in turn, flushing the lanes of
    /// `sums` (a LeafLaneSums) as the leaves add up, and last of all.
    template <class LaneSums, class Leaf>
    void forEachLeaf(const std::vector<FastLeafWork>& records, LaneSums& sums, Leaf leaf) const {
        std::size_t done = 0;
        for (const FastLeafWork& w : records) {
            for (std::size_t first = w.begin; first < w.begin + w.leaves * kLanes; first += kLanes)
                leaf(w, LeafColumns{qx_.data() + first, qy_.data() + first, qz_.data() + first,
                                    bx_.data() + first, by_.data() + first, bz_.data() + first,
                                    area_.data() + first, inverseLength2_.data() + first,
                                    inverseLength_.data() + first, valid_.data() + first});
            sums.leavesDone(done, w.leaves);
        }
        sums.flush();
    }
    /// The per-entry sums of every leaf in `leaves` (one pass, the call's constants set once).
    /// `skipDry`: leaves may come whole from a tile (waves), and those clear of the water are
    /// skipped after a first pass over their places.
    void perEntry(const std::vector<FastLeafWork>& leaves, const Mat3& R, const BodyState& s,
                  const Coefficients& k, bool skipDry, Sums& sum) const;
    /// The drag of every leaf in `leaves`, all of whose entries are wholly wet.
    void dragPerEntry(const std::vector<FastLeafWork>& leaves, const Mat3& R, const BodyState& s,
                      const Coefficients& k, Sums& sum) const;
    template <bool Friction>
    void dragLeaves(const std::vector<FastLeafWork>& leaves, const Mat3& R, const BodyState& s,
                    const Coefficients& k, Sums& sum) const;
    template <bool Friction, bool SkipDry>
    void perEntryLeaves(const std::vector<FastLeafWork>& leaves, const Mat3& R, const BodyState& s,
                        const Coefficients& k, Sums& sum) const;
    /// evaluate's body, compiled for the baseline and (evaluateAvx2) for AVX2 with FMA.
    Sums evaluateOn(const BodyState& state, const WaterSurface& water, const Coefficients& k,
                    FastScratch& scratch, FastStats* stats) const;
#ifdef PLIMSOLL_EVAL_AVX2_LOOPS
    PLIMSOLL_EVAL_AVX2_TARGET Sums evaluateAvx2(const BodyState& state, const WaterSurface& water,
                                                const Coefficients& k, FastScratch& scratch,
                                                FastStats* stats) const {
        return evaluateOn(state, water, k, scratch, stats);
    }
    template <bool Friction>
    PLIMSOLL_EVAL_AVX2_TARGET void dragLeavesAvx2(const std::vector<FastLeafWork>& leaves,
                                                  const Mat3& R, const BodyState& s,
                                                  const Coefficients& k, Sums& sum) const {
        dragLeaves<Friction>(leaves, R, s, k, sum);
    }
    template <bool Friction, bool SkipDry>
    PLIMSOLL_EVAL_AVX2_TARGET void perEntryLeavesAvx2(const std::vector<FastLeafWork>& leaves,
                                                      const Mat3& R, const BodyState& s,
                                                      const Coefficients& k, Sums& sum) const {
        perEntryLeaves<Friction, SkipDry>(leaves, R, s, k, sum);
    }
#endif

    FastOptions options_;
    Vec3 center_;
    double radius_ = 0;
    std::vector<float> qx_, qy_, qz_, bx_, by_, bz_, area_, inverseLength2_, inverseLength_, valid_;
    std::vector<FastTile> nodes_;
    std::vector<FastMoments> centerMoments_;
    std::vector<double>
        sinSpread_;  ///< sine of each node's cosSpread (same index; the drag's sign)
    std::uint32_t roots_ = 0;
    std::size_t tileCount_ = 0;
};

inline FastBody::DragSign FastBody::dragSign(const FastTile& t, double sinSpread, const Vec3& uo,
                                             const Vec3& wo, double spinRate,
                                             const Coefficients& k) const {
    if (k.halfRhoCf > 0) return DragSign::mixed;  // skin friction has no polynomial form
    // t_i = b_i.v_i with v_i = vc + wo x s_i (vc the velocity at the node's centre): its sign
    // over the node from the normal cone against vc, widened by the spin over the radius.
    const Vec3 vc = uo + cross(wo, t.center);
    const double speed2 = dot(vc, vc);
    const double spread = spinRate * t.radius;
    if (speed2 == 0 && spread == 0) return DragSign::away;  // at rest in still water: no drag
    // The largest and smallest component of the flow along a normal of the cone: with phi the
    // flow's angle from the axis and theta the cone's half-angle, V cos(phi - theta) (V itself
    // where phi <= theta) and V cos(phi + theta) (-V where phi + theta >= pi), V = |vc|. With
    // along = V cos(phi) and across = V sin(phi) they are along c +- across s (c, s the cosine
    // and sine of theta), compared squared: no square root (three were a fifth of the drag's
    // traversal).
    const double c = t.cosSpread, along = dot(t.axis, vc);
    const double across2 = std::max(0.0, speed2 - along * along), s2 = sinSpread * sinSpread;
    // x >= V y, V known only squared.
    auto atLeastSpeedTimes = [&](double x, double y) {
        return y >= 0 ? x >= 0 && x * x >= speed2 * y * y : x >= 0 || x * x <= speed2 * y * y;
    };
    // Away: the largest component at most -spread (never where the flow is inside the cone).
    if (!atLeastSpeedTimes(along, c)) {
        const double room = -(spread + along * c);  // -spread - along c >= across s
        if (room >= 0 && across2 * s2 <= room * room) return DragSign::away;
    }
    // Facing: the smallest above spread (never where the flow is against the cone).
    if (!atLeastSpeedTimes(-along, c)) {
        const double room = along * c - spread;  // along c - spread > across s
        if (room > 0 && room * room > across2 * s2) return DragSign::facing;
    }
    return DragSign::mixed;
}

inline void FastBody::dragFromMoments(const FastMoments& mo, const Vec3& center, const Vec3& uo,
                                      const Vec3& wo, const Coefficients& k, Vec3& force,
                                      Vec3& torque) {
    // Every entry faces the flow: D = -k sum (b.v) v with v = vc + wo x s, a polynomial in s
    // (file comment). b.(wo x s) = wo.(s x b), so a moment X[u][...] (u the area vector's axis,
    // the first index s's) contracts with the spin as spin(X) = wo.x (X[z][y] - X[y][z]) +
    // wo.y (X[x][z] - X[z][x]) + wo.z (X[y][x] - X[x][y]).
    const Vec3 vc = uo + cross(wo, center);
    const double v[3] = {vc.x, vc.y, vc.z};
    auto spin = [&](auto&& X) {
        return wo.x * (X(2, 1) - X(1, 2)) + wo.y * (X(0, 2) - X(2, 0)) + wo.z * (X(1, 0) - X(0, 1));
    };
    // sumT = sum b.v, St = sum (b.v) s, T = sum (b.v) s s^T (symmetric: its 6 slots).
    double sumT = mo.n0[0] * v[0] + mo.n0[1] * v[1] + mo.n0[2] * v[2] +
                  spin([&](int u, int j) { return mo.n1[u][j]; });
    double St[3], T[6];
    for (int l = 0; l < 3; ++l)
        St[l] = mo.n1[0][l] * v[0] + mo.n1[1][l] * v[1] + mo.n1[2][l] * v[2] +
                spin([&](int u, int j) { return mo.n2[u][kPair[j][l]]; });
    for (int slot = 0; slot < 6; ++slot) {
        const int l = kPairFirst[slot], n = kPairSecond[slot];
        T[slot] = mo.n2[0][slot] * v[0] + mo.n2[1][slot] * v[1] + mo.n2[2][slot] * v[2] +
                  spin([&](int u, int j) { return mo.n3[u][kTriple[j][l][n]]; });
    }
    const Vec3 st{St[0], St[1], St[2]};
    const Vec3 Tw{T[0] * wo.x + T[1] * wo.y + T[2] * wo.z, T[1] * wo.x + T[3] * wo.y + T[4] * wo.z,
                  T[2] * wo.x + T[4] * wo.y + T[5] * wo.z};
    const double trace = T[0] + T[3] + T[5];
    force = -k.halfRhoCd * (sumT * vc + cross(wo, st));
    // About `center`, then about c.
    torque = -k.halfRhoCd * (cross(st, vc) + trace * wo - Tw) + cross(center, force);
}

inline void FastBody::hydrostaticsFromDepthIntegrals(const FastDepthIntegrals& in, const Mat3& R,
                                                     const Coefficients& k, Sums& sum) {
    // The world's vertical is R's row y: the volume is -sum d b.y, the first moments -sum d b.y q
    // and, vertically, -sum (d q.y + d^2 / 2) b.y in world axes; pressure -rho g d b.
    const Vec3 rowY = R.row(1);
    const Vec3 d0{in.d0[0], in.d0[1], in.d0[2]};
    const Vec3 torque{in.d1[2][1] - in.d1[1][2], in.d1[0][2] - in.d1[2][0],
                      in.d1[1][0] - in.d1[0][1]};
    // rowY^T d1, then against each row of R.
    double y[3];
    for (int j = 0; j < 3; ++j)
        y[j] = rowY.x * in.d1[0][j] + rowY.y * in.d1[1][j] + rowY.z * in.d1[2][j];
    const Vec3 yD1{y[0], y[1], y[2]};
    sum.volume -= dot(rowY, d0);
    sum.moment.x -= dot(yD1, R.row(0));
    sum.moment.y -= dot(yD1, rowY) + 0.5 * dot(rowY, Vec3{in.e[0], in.e[1], in.e[2]});
    sum.moment.z -= dot(yD1, R.row(2));
    sum.pressureForce -= k.rhoG * (R * d0);
    sum.pressureTorque -= k.rhoG * (R * torque);
}

/// Calls f with `flag` as a compile-time constant (std::true_type or std::false_type), so that
/// a run-time choice picks one of a template's instances without writing each call out.
template <class F>
inline void withFlag(bool flag, F f) {
    if (flag)
        f(std::true_type{});
    else
        f(std::false_type{});
}

inline void FastBody::perEntry(const std::vector<FastLeafWork>& leaves, const Mat3& R,
                               const BodyState& s, const Coefficients& k, bool skipDry,
                               Sums& sum) const {
    if (leaves.empty()) return;
    withFlag(k.halfRhoCf > 0, [&](auto friction) {
        withFlag(skipDry, [&](auto skip) {
            constexpr bool Friction = decltype(friction)::value, SkipDry = decltype(skip)::value;
#ifdef PLIMSOLL_EVAL_AVX2_LOOPS
            if (cpuHasAvx2Fma()) return perEntryLeavesAvx2<Friction, SkipDry>(leaves, R, s, k, sum);
#endif
            perEntryLeaves<Friction, SkipDry>(leaves, R, s, k, sum);
        });
    });
}

/// Per-entry sums of the leaves: each leaf's Lanes entries add into Lanes single-precision
/// lanes per sum (a loop without a carried dependency across entries, so that it vectorises);
/// the lanes go to double every kFlush leaves, so that a lane adds few terms in single precision
/// (32: a lane's sum to about 1e-6 of its terms' at worst, a few 1e-7 typically; the flush,
/// scalar code, every 8 leaves was a twentieth of a call on waves, and the measured errors did
/// not move past 1e-10 of their scales between 8 and 32).
template <int Slots, std::size_t Lanes>
struct LeafLaneSums {
    static constexpr std::size_t kFlush = 32;
    alignas(32) float lanes[Slots][Lanes] = {};
    double total[Slots] = {};
    void flush() {
        for (int slot = 0; slot < Slots; ++slot)
            for (std::size_t l = 0; l < Lanes; ++l) {
                total[slot] += lanes[slot][l];
                lanes[slot][l] = 0;
            }
    }
    /// After `leaves` more leaves, n of them done before.
    void leavesDone(std::size_t& n, std::size_t leaves) {
        const std::size_t before = n / kFlush;
        n += leaves;
        if (n / kFlush != before) flush();
    }
};

/// The body's rotation and its angular velocity in the body's own axes, in single precision,
/// for the per-entry loops. The loops work in the body's axes: an entry's forces and torques
/// and its velocity relative to the water need no rotation there (their sums are turned into
/// world axes once, after the loop), and only what the water decides (an entry's height, the
/// vertical part of its area vector) is taken in world axes.
struct FloatRotation {
    float R[3][3];
    float wx, wy, wz;
    FloatRotation(const Mat3& rotation, const Vec3& bodyAngular)
        : wx(static_cast<float>(bodyAngular.x)),
          wy(static_cast<float>(bodyAngular.y)),
          wz(static_cast<float>(bodyAngular.z)) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) R[i][j] = static_cast<float>(rotation.m[i][j]);
    }
    /// An entry's position in world axes (relative to c).
    void place(const float q[3], float r[3]) const {
        for (int m = 0; m < 3; ++m) r[m] = R[m][0] * q[0] + R[m][1] * q[1] + R[m][2] * q[2];
    }
    /// The vertical (world y) component of a vector given in the body's axes.
    float vertical(const float b[3]) const {
        return R[1][0] * b[0] + R[1][1] * b[1] + R[1][2] * b[2];
    }
    /// An entry's velocity relative to the water, body axes: u (the body's, at c, relative to
    /// the water; body axes) plus the spin's part at q.
    void velocity(float ux, float uy, float uz, const float q[3], float v[3]) const {
        v[0] = ux + wy * q[2] - wz * q[1];
        v[1] = uy + wz * q[0] - wx * q[2];
        v[2] = uz + wx * q[1] - wy * q[0];
    }
};

template <bool Friction, bool SkipDry>
inline void FastBody::perEntryLeaves(const std::vector<FastLeafWork>& leaves, const Mat3& R,
                                     const BodyState& s, const Coefficients& k, Sums& sum) const {
    const FloatRotation rotation(R, transposeTimes(R, s.angular));
    const float rhoG = static_cast<float>(k.rhoG), halfRhoCd = static_cast<float>(k.halfRhoCd),
                halfRhoCf = static_cast<float>(k.halfRhoCf);
    LeafLaneSums<18, kLanes> sums;
    auto& lanes = sums.lanes;
    const double* total = sums.total;
    forEachLeaf(leaves, sums, [&](const FastLeafWork& w, const LeafColumns& column) {
        const float *qx = column.qx, *qy = column.qy, *qz = column.qz, *bx = column.bx,
                    *by = column.by, *bz = column.bz, *area = column.area,
                    *inverseLength2 = column.inverseLength2, *inverseLength = column.inverseLength,
                    *valid = column.valid;
        // First the entries' places and the water over them: a leaf whose entries are all
        // clear above the water adds nothing (no depth, no wetted share) and is skipped. At
        // the waterline of a tile on waves a quarter of the leaves are.
        // (On flat water the leaves were sorted before: none comes here dry, and one pass is
        // faster.)
        auto waterAt = [&](const float q[3], float r[3]) {
            rotation.place(q, r);
            const float dx = r[0] - w.cx, dz = r[2] - w.cz;
            return w.f + w.gx * dx + w.gz * dz + w.hxx * dx * dx + w.hxz * dx * dz +
                   w.hzz * dz * dz;
        };
        alignas(32) float rx[kLanes], ry[kLanes], rz[kLanes], height[kLanes];
        if constexpr (SkipDry) {
            int wet = 0;
            for (std::size_t i = 0; i < kLanes; ++i) {
                const float q[3] = {qx[i], qy[i], qz[i]};
                float r[3];
                height[i] = waterAt(q, r);
                rx[i] = r[0];
                ry[i] = r[1];
                rz[i] = r[2];
                wet |= r[1] - height[i] < w.dryAbove ? 1 : 0;
            }
            if (wet == 0) return;
        }
        for (std::size_t i = 0; i < kLanes; ++i) {
            float r[3], f;
            if constexpr (SkipDry) {
                r[0] = rx[i];
                r[1] = ry[i];
                r[2] = rz[i];
                f = height[i];
            } else {
                const float q[3] = {qx[i], qy[i], qz[i]};
                f = waterAt(q, r);
            }
            const float q[3] = {qx[i], qy[i], qz[i]}, b[3] = {bx[i], by[i], bz[i]};
            float v[3];
            rotation.velocity(w.ux, w.uy, w.uz, q, v);
            // Depth, volume and moments in world axes; forces and torques in the body's.
            const EntryTerms<float> e = entryTerms<float, Friction>(
                r, rotation.vertical(b), q, b, area[i], inverseLength2[i], inverseLength[i], f, v,
                rhoG, halfRhoCd, halfRhoCf);
            lanes[0][i] += e.volume;
            for (int m = 0; m < 3; ++m) {
                lanes[1 + m][i] += e.moment[m];
                lanes[4 + m][i] += e.pressureForce[m];
                lanes[7 + m][i] += e.pressureTorque[m];
                lanes[10 + m][i] += e.dragForce[m];
                lanes[13 + m][i] += e.dragTorque[m];
            }
            lanes[16][i] += e.wettedArea;
            lanes[17][i] += valid[i] * e.count;
        }
    });
    sum.volume += total[0];
    sum.moment += Vec3{total[1], total[2], total[3]};
    sum.pressureForce += R * Vec3{total[4], total[5], total[6]};
    sum.pressureTorque += R * Vec3{total[7], total[8], total[9]};
    sum.dragForce += R * Vec3{total[10], total[11], total[12]};
    sum.dragTorque += R * Vec3{total[13], total[14], total[15]};
    sum.wettedArea += total[16];
    sum.count += total[17];
}

inline void FastBody::dragPerEntry(const std::vector<FastLeafWork>& leaves, const Mat3& R,
                                   const BodyState& s, const Coefficients& k, Sums& sum) const {
    if (leaves.empty()) return;
    withFlag(k.halfRhoCf > 0, [&](auto friction) {
        constexpr bool Friction = decltype(friction)::value;
#ifdef PLIMSOLL_EVAL_AVX2_LOOPS
        if (cpuHasAvx2Fma()) return dragLeavesAvx2<Friction>(leaves, R, s, k, sum);
#endif
        dragLeaves<Friction>(leaves, R, s, k, sum);
    });
}

template <bool Friction>
inline void FastBody::dragLeaves(const std::vector<FastLeafWork>& leaves, const Mat3& R,
                                 const BodyState& s, const Coefficients& k, Sums& sum) const {
    // All in the body's axes (FloatRotation): no entry is rotated.
    const FloatRotation rotation(R, transposeTimes(R, s.angular));
    const float halfRhoCd = static_cast<float>(k.halfRhoCd),
                halfRhoCf = static_cast<float>(k.halfRhoCf);
    LeafLaneSums<6, kLanes> sums;
    auto& lanes = sums.lanes;
    const double* total = sums.total;
    forEachLeaf(leaves, sums, [&](const FastLeafWork& w, const LeafColumns& column) {
        const float *qx = column.qx, *qy = column.qy, *qz = column.qz, *bx = column.bx,
                    *by = column.by, *bz = column.bz, *area = column.area,
                    *inverseLength = column.inverseLength, *valid = column.valid;
        for (std::size_t i = 0; i < kLanes; ++i) {
            const float q[3] = {qx[i], qy[i], qz[i]};
            const float b[3] = {bx[i], by[i], bz[i]};
            float v[3];
            rotation.velocity(w.ux, w.uy, w.uz, q, v);
            float force[3], torque[3];
            entryDrag<float, Friction>(q, b, area[i], inverseLength[i], valid[i], v, halfRhoCd,
                                       halfRhoCf, force, torque);
            for (int m = 0; m < 3; ++m) {
                lanes[m][i] += force[m];
                lanes[3 + m][i] += torque[m];
            }
        }
    });
    sum.dragForce += R * Vec3{total[0], total[1], total[2]};
    sum.dragTorque += R * Vec3{total[3], total[4], total[5]};
}

inline Sums FastBody::evaluate(const BodyState& s, const WaterSurface& water, const Coefficients& k,
                               FastScratch& scratch, FastStats* stats) const {
#ifdef PLIMSOLL_EVAL_AVX2_LOOPS
    if (cpuHasAvx2Fma()) return evaluateAvx2(s, water, k, scratch, stats);
#endif
    return evaluateOn(s, water, k, scratch, stats);
}

inline Sums FastBody::evaluateOn(const BodyState& s, const WaterSurface& water,
                                 const Coefficients& k, FastScratch& scratch,
                                 FastStats* stats) const {
    FastStats counted;
    Sums sum;
    const Mat3& R = s.rotation;
    const double cy = s.center.y;
    if (roots_ == 0 || cy - radius_ >= water.maxHeight) {
        counted.dry = roots_;
        if (stats) *stats = counted;
        return sum;
    }
    // Waves: one batched query on a grid over the footprint (spacing h), heights relative to c.y.
    const bool waves = water.heights != nullptr;
    const int G = std::max(3, options_.waveGrid);
    const double half = radius_, h = 2 * half / (G - 1);
    const double x0 = s.center.x - half, z0 = s.center.z - half, inverseH = 1 / h;
    if (waves) {
        const std::size_t n = static_cast<std::size_t>(G) * G;
        scratch.x.resize(n);
        scratch.z.resize(n);
        scratch.h.resize(n);
        for (int j = 0; j < G; ++j)
            for (int i = 0; i < G; ++i) {
                scratch.x[j * G + i] = x0 + i * h;
                scratch.z[j * G + i] = z0 + j * h;
            }
        water.heights(water.context, n, scratch.x.data(), scratch.z.data(), s.time,
                      scratch.h.data());
        counted.waterSamples = n;
        // Each inner node's quadratic once, rather than once per node of the body that takes it.
        scratch.stencilQuadratics.resize(n);
        const double halfInverseH = 0.5 * inverseH, inverseH2 = inverseH * inverseH;
        for (int j = 1; j < G - 1; ++j)
            for (int i = 1; i < G - 1; ++i) {
                auto H = [&](int di, int dj) { return scratch.h[(j + dj) * G + (i + di)] - cy; };
                FastStencil& q = scratch.stencilQuadratics[j * G + i];
                q.f = H(0, 0);
                q.gx = (H(1, 0) - H(-1, 0)) * halfInverseH;
                q.gz = (H(0, 1) - H(0, -1)) * halfInverseH;
                q.hxx = (H(1, 0) - 2 * q.f + H(-1, 0)) * inverseH2;
                q.hzz = (H(0, 1) - 2 * q.f + H(0, -1)) * inverseH2;
                q.hxz = (H(1, 1) - H(1, -1) - H(-1, 1) + H(-1, -1)) * (0.25 * inverseH2);
                q.frobenius = std::sqrt(q.hxx * q.hxx + q.hzz * q.hzz + 2 * q.hxz * q.hxz);
            }
    }
    // The water's velocity is asked for once per call, in one batch, after the traversal: a
    // node that needs it takes a slot (a point of the batch) and its work on velocity waits.
    // `inherited`: the slot of the parent's centre, reused by its children (as before the
    // batch: a Gerstner velocity is the costly part of a query).
    const bool moving = water.moving();
    auto velocitySlot = [&](const Vec3& point) -> std::int32_t {
        scratch.px.push_back(point.x);
        scratch.py.push_back(point.y);
        scratch.pz.push_back(point.z);
        return static_cast<std::int32_t>(scratch.px.size() - 1);
    };
    // What a node's bounds say of it against the water, decided before anything is done with
    // it (below).
    enum class Wetness : std::uint8_t { dry, submerged, waterline };
    struct NodeWater {
        Vec3 rc;      // its centre about c, world axes
        TileWater w;  // the water over it, about its centre
        int stencil;  // on waves: the grid node whose 3 x 3 quadratic it takes
        Wetness wetness;
    };
    auto classify = [&](const FastTile& t, NodeWater& n) {
        n.rc = R * t.center;
        TileWater& w = n.w;
        // Bound of the water's departure from w.f over the tile: |g| r + |H|_F r^2 / 2, its
        // slope part kept squared (no square root on the traversal's critical path).
        double curvature = 0, slope2 = 0;
        n.stencil = -1;
        if (waves) {
            const double fx = (s.center.x + n.rc.x - x0) * inverseH,
                         fz = (s.center.z + n.rc.z - z0) * inverseH;
            // The nearest inner grid node (clamped before the conversion; a NaN goes to the edge).
            const int i = static_cast<int>(std::max(1.0, std::min(fx, G - 2.0)) + 0.5);
            const int j = static_cast<int>(std::max(1.0, std::min(fz, G - 2.0)) + 0.5);
            n.stencil = j * G + i;
            const FastStencil& q = scratch.stencilQuadratics[static_cast<std::size_t>(n.stencil)];
            w.hxx = q.hxx;
            w.hzz = q.hzz;
            w.hxz = q.hxz;
            const double dx = (fx - i) * h, dz = (fz - j) * h;  // tile centre from the node
            w.f = q.f + q.gx * dx + q.gz * dz + 0.5 * w.hxx * dx * dx + w.hxz * dx * dz +
                  0.5 * w.hzz * dz * dz;
            w.gx = q.gx + w.hxx * dx + w.hxz * dz;
            w.gz = q.gz + w.hxz * dx + w.hzz * dz;
            slope2 = (w.gx * w.gx + w.gz * w.gz) * t.radius * t.radius;
            curvature = 0.5 * q.frobenius * t.radius * t.radius;
        } else {
            w.f = water.level - cy;
        }
        // The tile's vertical reach: its box seen through R, or its sphere if that is smaller.
        const double reach = std::min(t.radius, std::abs(R.m[1][0]) * t.halfSize.x +
                                                    std::abs(R.m[1][1]) * t.halfSize.y +
                                                    std::abs(R.m[1][2]) * t.halfSize.z);
        const double top = n.rc.y + reach + t.halfExtent, bottom = n.rc.y - reach - t.halfExtent;
        // On waves a node is summed under the quadratic of the grid node nearest its centre. A
        // group is, only where it is small against the grid: its reach at most half the
        // spacing, so that every entry lies within the 3 x 3 nodes that quadratic was fitted
        // to (on a large texture most groups are; on a small one they span too much of the
        // surface, and their tiles decide, as tiles always do).
        // Dry: bottom >= w.f + variation; submerged: top < w.f - variation, with variation =
        // |g| r + curvature and the |g| r part compared squared.
        const double clearAbove = bottom - w.f - curvature, clearBelow = w.f - curvature - top;
        n.wetness = clearAbove >= 0 && clearAbove * clearAbove >= slope2 ? Wetness::dry
                    : clearBelow > 0 && clearBelow * clearBelow > slope2 &&
                            !(waves && isGroup(t) && t.radius + t.halfExtent > 0.5 * h)
                        ? Wetness::submerged
                        : Wetness::waterline;
    };
    // Nodes are looked at a few siblings at a time: all classified first, then acted on. Their
    // classifications are independent chains of arithmetic that the processor overlaps; one
    // node at a time, each waited for the last (the traversal took a third of the call).
    constexpr std::uint32_t kSiblings = 8;
    auto visit = [&](std::uint32_t first, std::uint32_t count, std::int32_t inherited,
                     auto& self) -> void {
        for (std::uint32_t from = first; from < first + count; from += kSiblings) {
            const std::uint32_t m = std::min(kSiblings, first + count - from);
            NodeWater found[kSiblings];
            for (std::uint32_t c = 0; c < m; ++c) classify(nodes_[from + c], found[c]);
            for (std::uint32_t c = 0; c < m; ++c) {
                const FastTile& t = nodes_[from + c];
                const NodeWater& n = found[c];
                if (n.wetness == Wetness::dry) {
                    ++counted.dry;
                    continue;
                }
                const bool group = isGroup(t);
                // The node's water-velocity sample: its parent's, or one at its centre.
                auto ownSlot = [&] {
                    return inherited >= 0 ? inherited : moving ? velocitySlot(s.center + n.rc) : -1;
                };
                if (n.wetness == Wetness::waterline) {
                    // A waterline tile's leaves take the sample at the tile's centre
                    // (docs/fast-path.md): one query for all of them rather than one each. A
                    // group's tiles take their own.
                    if (t.children > 0 && (group || !waves)) {
                        self(t.firstChild, t.children, group ? inherited : ownSlot(), self);
                        continue;
                    }
                    // On waves a waterline tile's leaves are all evaluated entry by entry, under
                    // the tile's water: sorting them into dry, submerged and waterline (each
                    // placed on the wave grid) cost more than evaluating them. On flat water
                    // sorting is cheap and the leaves decide (sphere at 64^2 moving on waves:
                    // 30 -> 26 us a call; at rest on flat water, all leaves cost 7.5 -> 9.9 us).
                    // A leaf reached here is its own one leaf.
                    const TileWater& w = n.w;
                    const std::int32_t slot = ownSlot();
                    // One record for the tile's leaves (consecutive entries from its first).
                    const std::uint32_t leafCount = t.children > 0 ? t.children : 1;
                    counted.perEntry += leafCount;
                    FastLeafWork& leaf = scratch.leaves.emplace_back();
                    leaf.begin = t.begin;
                    leaf.leaves = leafCount;
                    leaf.cx = static_cast<float>(n.rc.x);
                    leaf.cz = static_cast<float>(n.rc.z);
                    leaf.f = static_cast<float>(w.f);
                    leaf.gx = static_cast<float>(w.gx);
                    leaf.gz = static_cast<float>(w.gz);
                    leaf.hxx = static_cast<float>(0.5 * w.hxx);
                    leaf.hxz = static_cast<float>(w.hxz);
                    leaf.hzz = static_cast<float>(0.5 * w.hzz);
                    leaf.dryAbove = static_cast<float>(t.halfExtent * (1 + 1e-3) + 1e-6);
                    leaf.slot = slot;  // the relative velocity comes after the batch
                    continue;
                }
                ++counted.closedForm;
                // Drag waits for the water's velocity (below).
                const std::size_t index = static_cast<std::size_t>(&t - nodes_.data());
                scratch.drags.push_back({static_cast<std::uint32_t>(index), ownSlot()});
                // Under one water plane every submerged node's polynomial is the same: their
                // moments about c add up and are evaluated once (below).
                if (waves) {
                    // Every node of one stencil has the same quadratic: their moments about c add
                    // up in the stencil's bucket, evaluated once about the stencil's point (below).
                    std::int32_t& bucket =
                        scratch.stencilBucket[static_cast<std::size_t>(n.stencil)];
                    if (bucket < 0) {
                        bucket = static_cast<std::int32_t>(scratch.stencilCount);
                        FastStencilBucket& fresh =
                            nextBucket(scratch.stencils, scratch.stencilCount);
                        fresh.moments.clear();
                        fresh.node = n.stencil;
                        fresh.heightSum = fresh.entries = 0;
                    }
                    FastStencilBucket& into = scratch.stencils[static_cast<std::size_t>(bucket)];
                    into.moments.add(centerMoments_[index]);
                    into.heightSum += t.count * n.rc.y;
                    into.entries += t.count;
                } else {
                    scratch.flatHydrostatics.add(centerMoments_[index]);
                }
                sum.wettedArea += t.areaSum;
                sum.count += t.count;
            }
        }
    };
    scratch.leaves.clear();
    scratch.dragLeaves.clear();
    scratch.drags.clear();
    scratch.px.clear();
    scratch.py.clear();
    scratch.pz.clear();
    scratch.flatHydrostatics.clear();
    scratch.stencilCount = 0;
    if (waves) scratch.stencilBucket.assign(static_cast<std::size_t>(G) * G, -1);
    visit(0, roots_, -1, visit);
    // Waves: each stencil's bucket under the stencil's quadratic, about the point above its grid
    // node at the mean height of its nodes' centres (where depthIntegrals' left-out term is
    // smallest).
    for (std::size_t b = 0; b < scratch.stencilCount; ++b) {
        FastStencilBucket& bucket = scratch.stencils[b];
        const int node = bucket.node;
        const int i = node % G, j = node / G;
        const FastStencil& q = scratch.stencilQuadratics[static_cast<std::size_t>(node)];
        const TileWater w{q.f, q.gx, q.gz, q.hxx, q.hxz, q.hzz};  // about the node itself
        const Vec3 rp{x0 + i * h - s.center.x, bucket.heightSum / bucket.entries,
                      z0 + j * h - s.center.z};
        const Vec3 p = transposeTimes(R, rp);
        double H[3][3];
        objectHessian(R, w.hxx, w.hxz, w.hzz, H);
        // The depth about p: the height above the node less p's, falling with the slope.
        const Vec3 beta = transposeTimes(R, Vec3{w.gx, -1.0, w.gz});
        hydrostaticsFromDepthIntegrals(
            depthIntegrals(bucket.moments.moments(), p, w.f - rp.y, beta, H), R, k, sum);
    }
    if (!waves && !scratch.drags.empty()) {
        const double none[3][3] = {};
        const FastDepthIntegrals flat =
            depthIntegrals(scratch.flatHydrostatics.moments(2), Vec3{}, water.level - cy,
                           transposeTimes(R, Vec3{0, -1, 0}), none);
        hydrostaticsFromDepthIntegrals(flat, R, k, sum);
    }
    // The water's velocity at every slot, in one batch.
    const std::size_t points = scratch.px.size();
    scratch.velocity.assign(3 * points, 0.0);
    if (points > 0) {
        if (water.velocities) {
            water.velocities(water.context, points, scratch.px.data(), scratch.py.data(),
                             scratch.pz.data(), s.time, scratch.velocity.data());
        } else {
            for (std::size_t i = 0; i < points; ++i) {
                const Vec3 v = water.velocity(
                    water.context, {scratch.px[i], scratch.py[i], scratch.pz[i]}, s.time);
                scratch.velocity[3 * i] = v.x;
                scratch.velocity[3 * i + 1] = v.y;
                scratch.velocity[3 * i + 2] = v.z;
            }
        }
        counted.velocitySamples = points;
    }
    // What the drag and the per-entry loops take of it: the body's velocity relative to the
    // water at each slot, in the body's axes, formed once a slot (in place) rather than once for
    // each node, bucket and record that reads it; slot -1: still water.
    for (std::size_t i = 0; i < points; ++i) {
        double* v = scratch.velocity.data() + 3 * i;
        const Vec3 u = transposeTimes(R, s.linear - Vec3{v[0], v[1], v[2]});
        v[0] = u.x;
        v[1] = u.y;
        v[2] = u.z;
    }
    const Vec3 relativeInStillWater = transposeTimes(R, s.linear);
    auto relativeVelocityAt = [&](std::int32_t slot) {
        if (slot < 0) return relativeInStillWater;
        const double* v = scratch.velocity.data() + 3 * static_cast<std::size_t>(slot);
        return Vec3{v[0], v[1], v[2]};
    };
    for (FastLeafWork& leaf : scratch.leaves) {
        const Vec3 u = relativeVelocityAt(leaf.slot);
        leaf.ux = static_cast<float>(u.x);
        leaf.uy = static_cast<float>(u.y);
        leaf.uz = static_cast<float>(u.z);
    }
    // Drag: the largest nodes whose entries all face the flow add their moments to the bucket
    // of their water velocity (one per slot; one in all on still water); per entry (drag alone:
    // every entry is wholly wet) in the leaves where the sign changes.
    scratch.bucketOfSlot.assign(points + 1, -1);
    scratch.dragBucketCount = 0;
    const Vec3 wo = transposeTimes(R, s.angular);
    const double spinRate = norm(wo);
    for (const FastDeferredDrag& deferred : scratch.drags) {
        const Vec3 uo = relativeVelocityAt(deferred.slot);
        if (dot(uo, uo) == 0 && dot(wo, wo) == 0) continue;  // no flow: no drag (nor friction)
        auto drag = [&](const FastTile& node, auto& again) -> void {
            const std::size_t index = static_cast<std::size_t>(&node - nodes_.data());
            // A leaf's 8 entries, one by one in one vectorised pass, cost less than its sign
            // test (and than adding its moments): leaves never take the test.
            switch (node.children == 0 ? DragSign::mixed
                                       : dragSign(node, sinSpread_[index], uo, wo, spinRate, k)) {
                case DragSign::away:
                    return;
                case DragSign::facing: {
                    std::int32_t& bucket =
                        scratch.bucketOfSlot[static_cast<std::size_t>(deferred.slot + 1)];
                    if (bucket < 0) {
                        bucket = static_cast<std::int32_t>(scratch.dragBucketCount);
                        FastBucket& fresh =
                            nextBucket(scratch.dragBuckets, scratch.dragBucketCount);
                        fresh.moments.clear();
                        fresh.slot = deferred.slot;
                    }
                    scratch.dragBuckets[static_cast<std::size_t>(bucket)].moments.add(
                        centerMoments_[index]);
                    return;
                }
                case DragSign::mixed:
                    break;
            }
            if (isGroup(node)) {
                for (std::uint32_t c = 0; c < node.children; ++c)
                    again(nodes_[node.firstChild + c], again);
                return;
            }
            // A tile's leaves (or a leaf) in one record: their entries are consecutive.
            const std::uint32_t leafCount = node.children > 0 ? node.children : 1;
            counted.dragPerEntry += leafCount;
            FastLeafWork& leaf = scratch.dragLeaves.emplace_back();
            leaf.begin = node.begin;
            leaf.leaves = leafCount;
            leaf.ux = static_cast<float>(uo.x);
            leaf.uy = static_cast<float>(uo.y);
            leaf.uz = static_cast<float>(uo.z);
        };
        drag(nodes_[deferred.node], drag);
    }
    for (std::size_t b = 0; b < scratch.dragBucketCount; ++b) {
        FastBucket& bucket = scratch.dragBuckets[b];
        const Vec3 uo = relativeVelocityAt(bucket.slot);
        Vec3 force, torque;
        dragFromMoments(bucket.moments.moments(), Vec3{}, uo, wo, k, force, torque);
        sum.dragForce += R * force;
        sum.dragTorque += R * torque;
    }
    perEntry(scratch.leaves, R, s, k, waves, sum);
    dragPerEntry(scratch.dragLeaves, R, s, k, sum);
    if (stats) *stats = counted;
    return sum;
}

}  // namespace plimsoll_eval
