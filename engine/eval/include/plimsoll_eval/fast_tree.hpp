// The fast evaluation's tree (fast.hpp): a body's entries sorted along a Morton curve, in
// single precision and structure of arrays, grouped into three levels of nodes that are compact
// in object space (groups of tiles, tiles, leaves of kLanes entries). Each node keeps a bounding
// box and sphere, the spread of its normals and the moments of its area vectors about the body's
// centre c, from which a submerged node's sums come in closed form (fast_closed_forms.hpp). The
// evaluation walks the tree with a visitor (FastTree::walk).
#pragma once

#include "plimsoll_eval/vec.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace plimsoll_eval {

struct FastOptions {
    std::size_t tileSize = 32;  ///< entries per tile (rounded up to a power of two, 8 to 64)
    int waveGrid = 9;           ///< water samples per side of the footprint grid (>= 3)
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

/// What a visitor's visit tells FastTree::walk: whether to walk the node's children, and the
/// value they inherit (the evaluation's: a water-velocity slot).
struct FastWalkStep {
    bool descend = false;
    std::int32_t inherited = -1;
};

/// A body's entries in tile order (single precision, structure of arrays) and its nodes.
class FastTree {
public:
    static constexpr std::size_t kLanes = 8;       ///< entries per leaf: the per-entry sums' lanes
    static constexpr std::size_t kMaxTile = 64;    ///< entries per tile at most
    static constexpr std::size_t kGroupTiles = 8;  ///< tiles per group

    /// The columns of the kLanes entries of one leaf.
    struct LeafColumns {
        const float *qx, *qy, *qz, *bx, *by, *bz, *area, *inverseLength2, *inverseLength, *valid;
    };

    /// `entry(i, p, a, area)` fills entry i's position and area vector (object space) and area;
    /// `center` is the body's centre c.
    template <class Entry>
    void build(std::size_t count, Entry entry, const Vec3& center, const FastOptions& options) {
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
        const std::vector<std::uint32_t> order = mortonOrder(p, lo, hi);
        // Tiles of a power of two of entries, the last padded with entries that weigh nothing
        // (valid 0, zero area).
        std::size_t size = kLanes;
        while (size < std::min(options.tileSize, kMaxTile)) size *= 2;
        fillColumns(order, p, a, area, (count + size - 1) / size * size);
        buildLevels(size);
        centerMoments_.clear();
        sinSpread_.clear();
        for (const FastTile& t : nodes_) {
            momentsAbout(t.begin, t.end, Vec3{}, centerMoments_.emplace_back());
            sinSpread_.push_back(std::sqrt(std::max(0.0, 1.0 - t.cosSpread * t.cosSpread)));
        }
    }

    std::size_t size() const { return qx_.size(); }  ///< entries, padded to whole lanes
    /// Every node of the three levels (groups first; see build).
    const std::vector<FastTile>& nodes() const { return nodes_; }
    /// Their moments (same index) about the body's centre c (s = q): what buckets sum, and
    /// shift to a wave stencil's point where the depth is expanded about it.
    const std::vector<FastMoments>& centerMoments() const { return centerMoments_; }
    /// The sine of each node's cosSpread (same index; the drag's sign).
    double sinSpread(std::size_t node) const { return sinSpread_[node]; }
    /// The index of a node of nodes().
    std::size_t indexOf(const FastTile& t) const {
        return static_cast<std::size_t>(&t - nodes_.data());
    }
    /// Groups: the top level, the first nodes.
    std::uint32_t roots() const { return roots_; }
    /// Whether t is a group.
    bool isGroup(const FastTile& t) const { return &t < nodes_.data() + roots_; }
    /// Tiles of FastOptions::tileSize entries (the middle level).
    std::size_t tileCount() const { return tileCount_; }
    const Vec3& center() const { return center_; }
    /// Largest distance of an entry (with its half extent) from c.
    double radius() const { return radius_; }
    const FastOptions& options() const { return options_; }
    /// The columns of the leaf whose first entry is `first`.
    LeafColumns leafColumns(std::size_t first) const {
        return LeafColumns{qx_.data() + first,
                           qy_.data() + first,
                           qz_.data() + first,
                           bx_.data() + first,
                           by_.data() + first,
                           bz_.data() + first,
                           area_.data() + first,
                           inverseLength2_.data() + first,
                           inverseLength_.data() + first,
                           valid_.data() + first};
    }
    /// Heap bytes the tree holds (entries' columns, nodes, their moments).
    std::size_t memoryBytes() const {
        std::size_t bytes = 0;
        for (const auto* column : {&qx_, &qy_, &qz_, &bx_, &by_, &bz_, &area_, &inverseLength2_,
                                   &inverseLength_, &valid_})
            bytes += column->capacity() * sizeof(float);
        return bytes + nodes_.capacity() * sizeof(FastTile) +
               centerMoments_.capacity() * sizeof(FastMoments) +
               sinSpread_.capacity() * sizeof(double);
    }

    /// Walks nodes [first, first + count) and, depth first, the children the visitor asks for.
    /// Siblings are taken a few at a time: each first classified (`visitor.classify(node,
    /// found)`, a `Visitor::Found`), then visited in order (`visitor.visit(node, found,
    /// inherited)`, a FastWalkStep). Classifications are independent chains of arithmetic
    /// that the processor overlaps; one node at a time, each waited for the last (the
    /// traversal took a third of an evaluation).
    template <class Visitor>
    void walk(std::uint32_t first, std::uint32_t count, std::int32_t inherited,
              Visitor& visitor) const {
        walkLevel<0>(first, count, inherited, visitor);
    }

    /// walk from one node: it, then the children its visit asks for (no loop over siblings).
    template <class Visitor>
    void walkFrom(const FastTile& node, std::int32_t inherited, Visitor& visitor) const {
        typename Visitor::Found found;
        visitor.classify(node, found);
        const FastWalkStep step = visitor.visit(node, found, inherited);
        if (step.descend) walkLevel<1>(node.firstChild, node.children, step.inherited, visitor);
    }

private:
    /// The tree's levels below a walk's first nodes: groups, tiles, leaves (which have no
    /// children).
    static constexpr int kLevels = 3;

    /// walk at one depth. A function per depth rather than recursion: the evaluation's
    /// instruction-set builds (fast_isa.hpp) inline every call of their body, and a recursive
    /// call would stay one function built for the baseline.
    template <int Level, class Visitor>
    void walkLevel(std::uint32_t first, std::uint32_t count, std::int32_t inherited,
                   Visitor& visitor) const {
        constexpr std::uint32_t kSiblings = 8;
        for (std::uint32_t from = first; from < first + count; from += kSiblings) {
            const std::uint32_t m = std::min(kSiblings, first + count - from);
            typename Visitor::Found found[kSiblings];
            for (std::uint32_t c = 0; c < m; ++c) visitor.classify(nodes_[from + c], found[c]);
            for (std::uint32_t c = 0; c < m; ++c) {
                const FastTile& t = nodes_[from + c];
                const FastWalkStep step = visitor.visit(t, found[c], inherited);
                if constexpr (Level + 1 < kLevels) {
                    if (step.descend)
                        walkLevel<Level + 1>(t.firstChild, t.children, step.inherited, visitor);
                }
            }
        }
    }

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

    /// The entries' order along a Morton curve over their bounds [lo, hi]: tiles of consecutive
    /// entries are then compact in object space.
    static std::vector<std::uint32_t> mortonOrder(const std::vector<Vec3>& p, const Vec3& lo,
                                                  const Vec3& hi) {
        const std::size_t count = p.size();
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
        return order;
    }

    /// The columns in `order`, `padded` entries long.
    void fillColumns(const std::vector<std::uint32_t>& order, const std::vector<Vec3>& p,
                     const std::vector<Vec3>& a, const std::vector<double>& area,
                     std::size_t padded) {
        for (auto* column : {&qx_, &qy_, &qz_, &bx_, &by_, &bz_, &area_, &inverseLength2_,
                             &inverseLength_, &valid_})
            column->assign(padded, 0.0f);
        for (std::size_t i = 0; i < order.size(); ++i) {
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
    }

    /// The nodes over the columns, tiles of `size` entries: three levels, all compact in object
    /// space along the Morton order: groups of kGroupTiles tiles, tiles, leaves of kLanes
    /// entries. A node that is neither dry nor summable in closed form is looked at again in
    /// its children; only leaves are evaluated per entry.
    void buildLevels(std::size_t size) {
        const std::size_t padded = qx_.size();
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
        radius_ = 0;
        for (const FastTile& t : tiles)
            radius_ = std::max(radius_, norm(t.center) + t.radius + t.halfExtent);
    }

    FastOptions options_;
    Vec3 center_;
    double radius_ = 0;
    std::vector<float> qx_, qy_, qz_, bx_, by_, bz_, area_, inverseLength2_, inverseLength_, valid_;
    std::vector<FastTile> nodes_;
    std::vector<FastMoments> centerMoments_;
    std::vector<double> sinSpread_;
    std::uint32_t roots_ = 0;
    std::size_t tileCount_ = 0;
};

}  // namespace plimsoll_eval
