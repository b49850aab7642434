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
//
// The parts, each a header: the tree (fast_tree.hpp: entries, nodes, moments, the walk), the
// closed forms (fast_closed_forms.hpp), the per-entry leaves (fast_leaves.hpp) and the
// instruction set (fast_isa.hpp). This one holds the call: FastBody::evaluate, its steps in
// the order they run.
#pragma once

#include "plimsoll_eval/entry.hpp"
#include "plimsoll_eval/fast_closed_forms.hpp"
#include "plimsoll_eval/fast_isa.hpp"
#include "plimsoll_eval/fast_leaves.hpp"
#include "plimsoll_eval/fast_tree.hpp"
#include "plimsoll_eval/vec.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace plimsoll_eval {

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

/// The next of a call's buckets in `pool`, whose first `used` are taken: entries are reused
/// from call to call (not cleared), so the caller sets every field; the pool grows only on the
/// first calls.
template <class Bucket>
inline Bucket& nextBucket(std::vector<Bucket>& pool, std::size_t& used) {
    if (pool.size() <= used) pool.emplace_back();
    return pool[used++];
}

/// A submerged node whose drag waits for the water's velocity (one batched query per call).
struct FastDeferredDrag {
    std::uint32_t node = 0;
    std::int32_t slot = -1;  ///< its point in FastScratch's velocity batch; -1: still water
};

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

/// A body's tree and its evaluation for one state.
class FastBody {
public:
    /// `entry(i, p, a, area)` fills entry i's position and area vector (object space) and area;
    /// `center` is the body's centre c.
    template <class Entry>
    void build(std::size_t count, Entry entry, const Vec3& center,
               const FastOptions& options = {}) {
        tree_.build(count, entry, center, options);
    }

    std::size_t size() const { return tree_.size(); }  ///< entries, padded to whole lanes
    /// Every node of the three levels (groups first; see FastTree::build).
    const std::vector<FastTile>& nodes() const { return tree_.nodes(); }
    /// Their moments (same index) about the body's centre c.
    const std::vector<FastMoments>& centerMoments() const { return tree_.centerMoments(); }
    /// Tiles of FastOptions::tileSize entries (the middle level).
    std::size_t tileCount() const { return tree_.tileCount(); }
    const Vec3& center() const { return tree_.center(); }
    /// Largest distance of an entry (with its half extent) from c.
    double radius() const { return tree_.radius(); }
    const FastOptions& options() const { return tree_.options(); }
    /// Heap bytes the tree holds.
    std::size_t memoryBytes() const { return tree_.memoryBytes(); }

    /// The body's sums about c for one state (see the file comment).
    Sums evaluate(const BodyState& state, const WaterSurface& water, const Coefficients& k,
                  FastScratch& scratch, FastStats* stats = nullptr) const;

private:
    /// The wave grid over the body's footprint: G x G points spaced h from (x0, z0).
    struct WaveGrid {
        bool waves = false;
        int G = 3;
        double h = 0, x0 = 0, z0 = 0, inverseH = 0;
    };
    /// The water over one node: f(d) = f + g.d + d^T H d / 2 relative to c.y, d the horizontal
    /// offset from the node's centre (world axes). (Its velocity is a slot of the call's batch.)
    struct TileWater {
        double f = 0, gx = 0, gz = 0, hxx = 0, hxz = 0, hzz = 0;
    };
    class NodeVisitor;
    class DragVisitor;

    /// evaluate's body, compiled for the baseline and (evaluateAvx2) for AVX2.
    Sums evaluateOn(const BodyState& state, const WaterSurface& water, const Coefficients& k,
                    FastScratch& scratch, FastStats* stats) const;
#ifdef PLIMSOLL_EVAL_AVX2_LOOPS
    PLIMSOLL_EVAL_AVX2_TARGET Sums evaluateAvx2(const BodyState& state, const WaterSurface& water,
                                                const Coefficients& k, FastScratch& scratch,
                                                FastStats* stats) const {
        return evaluateOn(state, water, k, scratch, stats);
    }
#endif
    /// The grid, and on waves its heights (one batched query) and each inner grid node's
    /// quadratic through its 3 x 3 stencil.
    WaveGrid sampleWaves(const BodyState& s, const WaterSurface& water, FastScratch& scratch,
                         FastStats& counted) const;
    /// Empties the call's lists and buckets (their storage is kept).
    static void clearScratch(const WaveGrid& grid, FastScratch& scratch);
    /// Waves: each stencil's bucket under the stencil's quadratic.
    static void stencilHydrostatics(const WaveGrid& grid, const BodyState& s, const Coefficients& k,
                                    FastScratch& scratch, Sums& sum);
    /// The water's velocity at every slot, in one batch, then (in place) the body's velocity
    /// relative to it in the body's axes.
    static void relativeVelocities(const BodyState& s, const WaterSurface& water,
                                   FastScratch& scratch, FastStats& counted);
    /// Drag of the nodes the walk left for it (FastDeferredDrag): by buckets of moments where
    /// every entry faces the flow, per entry where the sign changes.
    void drag(const BodyState& s, const Coefficients& k, FastScratch& scratch, Sums& sum,
              FastStats& counted) const;

    FastTree tree_;
};

/// The walk's visitor: what a node's bounds say of it against the water (dry, submerged or at
/// the waterline), decided for a few siblings before any is acted on; then a dry node adds
/// nothing, a submerged one adds its moments to the closed form of its water, and a waterline
/// one is looked at again in its children or, a tile on waves or a leaf, left to per-entry work.
class FastBody::NodeVisitor {
public:
    enum class Wetness : std::uint8_t { dry, submerged, waterline };
    struct Found {
        Vec3 rc;      // its centre about c, world axes
        TileWater w;  // the water over it, about its centre
        int stencil;  // on waves: the grid node whose 3 x 3 quadratic it takes
        Wetness wetness;
    };

    NodeVisitor(const FastTree& tree, const WaveGrid& grid, const BodyState& s,
                const WaterSurface& water, FastScratch& scratch, Sums& sum, FastStats& counted)
        : tree_(tree),
          grid_(grid),
          s_(s),
          R_(s.rotation),
          water_(water),
          moving_(water.moving()),
          scratch_(scratch),
          sum_(sum),
          counted_(counted) {}

    void classify(const FastTile& t, Found& n) const;
    FastWalkStep visit(const FastTile& t, const Found& n, std::int32_t inherited);

private:
    /// A new point of the water-velocity batch (asked for once per call, after the walk: a node
    /// that needs it takes a slot and its work on velocity waits).
    std::int32_t velocitySlot(const Vec3& point) {
        scratch_.px.push_back(point.x);
        scratch_.py.push_back(point.y);
        scratch_.pz.push_back(point.z);
        return static_cast<std::int32_t>(scratch_.px.size() - 1);
    }
    void leaveToEntries(const FastTile& t, const Found& n, std::int32_t slot);
    void addClosedForm(const FastTile& t, const Found& n, std::int32_t slot);

    const FastTree& tree_;
    const WaveGrid grid_;
    const BodyState& s_;
    const Mat3 R_;
    const WaterSurface& water_;
    const bool moving_;
    FastScratch& scratch_;
    Sums& sum_;
    FastStats& counted_;
};

inline void FastBody::NodeVisitor::classify(const FastTile& t, Found& n) const {
    const Mat3& R = R_;
    const BodyState& s = s_;
    const bool waves = grid_.waves;
    const int G = grid_.G;
    const double h = grid_.h, x0 = grid_.x0, z0 = grid_.z0, inverseH = grid_.inverseH;
    const double cy = s.center.y;
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
        const FastStencil& q = scratch_.stencilQuadratics[static_cast<std::size_t>(n.stencil)];
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
        w.f = water_.level - cy;
    }
    // The tile's vertical reach: its box seen through R, or its sphere if that is smaller.
    const double reach =
        std::min(t.radius, std::abs(R.m[1][0]) * t.halfSize.x + std::abs(R.m[1][1]) * t.halfSize.y +
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
                        !(waves && tree_.isGroup(t) && t.radius + t.halfExtent > 0.5 * h)
                    ? Wetness::submerged
                    : Wetness::waterline;
}

inline FastWalkStep FastBody::NodeVisitor::visit(const FastTile& t, const Found& n,
                                                 std::int32_t inherited) {
    if (n.wetness == Wetness::dry) {
        ++counted_.dry;
        return {};
    }
    const bool group = tree_.isGroup(t);
    // The node's water-velocity sample: its parent's, or one at its centre.
    auto ownSlot = [&] {
        return inherited >= 0 ? inherited : moving_ ? velocitySlot(s_.center + n.rc) : -1;
    };
    if (n.wetness == Wetness::waterline) {
        // A waterline tile's leaves take the sample at the tile's centre (docs/fast-path.md):
        // one query for all of them rather than one each. A group's tiles take their own.
        if (t.children > 0 && (group || !grid_.waves)) return {true, group ? inherited : ownSlot()};
        // On waves a waterline tile's leaves are all evaluated entry by entry, under the tile's
        // water: sorting them into dry, submerged and waterline (each placed on the wave grid)
        // cost more than evaluating them. On flat water sorting is cheap and the leaves decide
        // (sphere at 64^2 moving on waves: 30 -> 26 us a call; at rest on flat water, all
        // leaves cost 7.5 -> 9.9 us). A leaf reached here is its own one leaf.
        leaveToEntries(t, n, ownSlot());
        return {};
    }
    addClosedForm(t, n, ownSlot());
    return {};
}

inline void FastBody::NodeVisitor::leaveToEntries(const FastTile& t, const Found& n,
                                                  std::int32_t slot) {
    const TileWater& w = n.w;
    // One record for the tile's leaves (consecutive entries from its first).
    const std::uint32_t leafCount = t.children > 0 ? t.children : 1;
    counted_.perEntry += leafCount;
    FastLeafWork& leaf = scratch_.leaves.emplace_back();
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
}

inline void FastBody::NodeVisitor::addClosedForm(const FastTile& t, const Found& n,
                                                 std::int32_t slot) {
    ++counted_.closedForm;
    // Drag waits for the water's velocity (FastBody::drag).
    const std::size_t index = tree_.indexOf(t);
    scratch_.drags.push_back({static_cast<std::uint32_t>(index), slot});
    const FastMoments& moments = tree_.centerMoments()[index];
    if (grid_.waves) {
        // Every node of one stencil has the same quadratic: their moments about c add up in the
        // stencil's bucket, evaluated once about the stencil's point (stencilHydrostatics).
        std::int32_t& bucket = scratch_.stencilBucket[static_cast<std::size_t>(n.stencil)];
        if (bucket < 0) {
            bucket = static_cast<std::int32_t>(scratch_.stencilCount);
            FastStencilBucket& fresh = nextBucket(scratch_.stencils, scratch_.stencilCount);
            fresh.moments.clear();
            fresh.node = n.stencil;
            fresh.heightSum = fresh.entries = 0;
        }
        FastStencilBucket& into = scratch_.stencils[static_cast<std::size_t>(bucket)];
        into.moments.add(moments);
        into.heightSum += t.count * n.rc.y;
        into.entries += t.count;
    } else {
        // Under one water plane every submerged node's polynomial is the same: their moments
        // about c add up and are evaluated once.
        scratch_.flatHydrostatics.add(moments);
    }
    sum_.wettedArea += t.areaSum;
    sum_.count += t.count;
}

/// The drag walk's visitor, from one submerged node down, for one water velocity (uo, relative,
/// body axes) and spin wo: the largest nodes whose entries all face the flow add their moments to
/// the bucket of that velocity's slot; per entry (drag alone: every entry is wholly wet) in the
/// tiles where the sign changes.
class FastBody::DragVisitor {
public:
    using Found = FastDragSign;

    DragVisitor(const FastTree& tree, const Vec3& uo, const Vec3& wo, double spinRate,
                const Coefficients& k, FastScratch& scratch, FastStats& counted)
        : tree_(tree),
          uo_(uo),
          wo_(wo),
          spinRate_(spinRate),
          k_(k),
          scratch_(scratch),
          counted_(counted) {}

    void classify(const FastTile& node, FastDragSign& sign) const {
        // A leaf's 8 entries, one by one in one vectorised pass, cost less than its sign test
        // (and than adding its moments): leaves never take the test.
        sign = node.children == 0
                   ? FastDragSign::mixed
                   : dragSign(node, tree_.sinSpread(tree_.indexOf(node)), uo_, wo_, spinRate_, k_);
    }

    FastWalkStep visit(const FastTile& node, FastDragSign sign, std::int32_t slot) {
        switch (sign) {
            case FastDragSign::away:
                return {};
            case FastDragSign::facing: {
                std::int32_t& bucket = scratch_.bucketOfSlot[static_cast<std::size_t>(slot + 1)];
                if (bucket < 0) {
                    bucket = static_cast<std::int32_t>(scratch_.dragBucketCount);
                    FastBucket& fresh = nextBucket(scratch_.dragBuckets, scratch_.dragBucketCount);
                    fresh.moments.clear();
                    fresh.slot = slot;
                }
                scratch_.dragBuckets[static_cast<std::size_t>(bucket)].moments.add(
                    tree_.centerMoments()[tree_.indexOf(node)]);
                return {};
            }
            case FastDragSign::mixed:
                break;
        }
        if (tree_.isGroup(node)) return {true, slot};
        // A tile's leaves (or a leaf) in one record: their entries are consecutive.
        const std::uint32_t leafCount = node.children > 0 ? node.children : 1;
        counted_.dragPerEntry += leafCount;
        FastLeafWork& leaf = scratch_.dragLeaves.emplace_back();
        leaf.begin = node.begin;
        leaf.leaves = leafCount;
        leaf.ux = static_cast<float>(uo_.x);
        leaf.uy = static_cast<float>(uo_.y);
        leaf.uz = static_cast<float>(uo_.z);
        return {};
    }

private:
    const FastTree& tree_;
    const Vec3 uo_, wo_;
    const double spinRate_;
    const Coefficients& k_;
    FastScratch& scratch_;
    FastStats& counted_;
};

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
    if (tree_.roots() == 0 || s.center.y - tree_.radius() >= water.maxHeight) {
        counted.dry = tree_.roots();
        if (stats) *stats = counted;
        return sum;
    }
    const WaveGrid grid = sampleWaves(s, water, scratch, counted);
    clearScratch(grid, scratch);
    NodeVisitor nodes(tree_, grid, s, water, scratch, sum, counted);
    tree_.walk(0, tree_.roots(), -1, nodes);
    stencilHydrostatics(grid, s, k, scratch, sum);
    if (!grid.waves && !scratch.drags.empty()) {
        const double none[3][3] = {};
        const FastDepthIntegrals flat =
            depthIntegrals(scratch.flatHydrostatics.moments(2), Vec3{}, water.level - s.center.y,
                           transposeTimes(s.rotation, Vec3{0, -1, 0}), none);
        hydrostaticsFromDepthIntegrals(flat, s.rotation, k, sum);
    }
    relativeVelocities(s, water, scratch, counted);
    drag(s, k, scratch, sum, counted);
    perEntrySums(tree_, scratch.leaves, s.rotation, s.angular, k, grid.waves, sum);
    dragPerEntrySums(tree_, scratch.dragLeaves, s.rotation, s.angular, k, sum);
    if (stats) *stats = counted;
    return sum;
}

inline FastBody::WaveGrid FastBody::sampleWaves(const BodyState& s, const WaterSurface& water,
                                                FastScratch& scratch, FastStats& counted) const {
    const double cy = s.center.y;
    // Waves: one batched query on a grid over the footprint (spacing h), heights relative to c.y.
    WaveGrid grid;
    grid.waves = water.heights != nullptr;
    const int G = grid.G = std::max(3, tree_.options().waveGrid);
    const double half = tree_.radius(), h = grid.h = 2 * half / (G - 1);
    const double x0 = grid.x0 = s.center.x - half, z0 = grid.z0 = s.center.z - half;
    const double inverseH = grid.inverseH = 1 / h;
    if (!grid.waves) return grid;
    const std::size_t n = static_cast<std::size_t>(G) * G;
    scratch.x.resize(n);
    scratch.z.resize(n);
    scratch.h.resize(n);
    for (int j = 0; j < G; ++j)
        for (int i = 0; i < G; ++i) {
            scratch.x[j * G + i] = x0 + i * h;
            scratch.z[j * G + i] = z0 + j * h;
        }
    water.heights(water.context, n, scratch.x.data(), scratch.z.data(), s.time, scratch.h.data());
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
    return grid;
}

inline void FastBody::clearScratch(const WaveGrid& grid, FastScratch& scratch) {
    scratch.leaves.clear();
    scratch.dragLeaves.clear();
    scratch.drags.clear();
    scratch.px.clear();
    scratch.py.clear();
    scratch.pz.clear();
    scratch.flatHydrostatics.clear();
    scratch.stencilCount = 0;
    if (grid.waves) scratch.stencilBucket.assign(static_cast<std::size_t>(grid.G) * grid.G, -1);
}

inline void FastBody::stencilHydrostatics(const WaveGrid& grid, const BodyState& s,
                                          const Coefficients& k, FastScratch& scratch, Sums& sum) {
    const Mat3& R = s.rotation;
    const int G = grid.G;
    const double h = grid.h, x0 = grid.x0, z0 = grid.z0;
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
}

inline void FastBody::relativeVelocities(const BodyState& s, const WaterSurface& water,
                                         FastScratch& scratch, FastStats& counted) {
    const Mat3& R = s.rotation;
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
}

inline void FastBody::drag(const BodyState& s, const Coefficients& k, FastScratch& scratch,
                           Sums& sum, FastStats& counted) const {
    const Mat3& R = s.rotation;
    const std::size_t points = scratch.px.size();
    const Vec3 relativeInStillWater = transposeTimes(R, s.linear);
    auto relativeVelocityAt = [&](std::int32_t slot) {
        if (slot < 0) return relativeInStillWater;
        const double* v = scratch.velocity.data() + 3 * static_cast<std::size_t>(slot);
        return Vec3{v[0], v[1], v[2]};
    };
    // The per-entry records take the relative velocity of their slot.
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
        DragVisitor visitor(tree_, uo, wo, spinRate, k, scratch, counted);
        tree_.walkFrom(tree_.nodes()[deferred.node], deferred.slot, visitor);
    }
    for (std::size_t b = 0; b < scratch.dragBucketCount; ++b) {
        FastBucket& bucket = scratch.dragBuckets[b];
        const Vec3 uo = relativeVelocityAt(bucket.slot);
        Vec3 force, torque;
        dragFromMoments(bucket.moments.moments(), Vec3{}, uo, wo, k, force, torque);
        sum.dragForce += R * force;
        sum.dragTorque += R * torque;
    }
}

}  // namespace plimsoll_eval
