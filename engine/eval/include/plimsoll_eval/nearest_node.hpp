// The node a surface point feeds (paper 4.2: a texel exchanges with its nearest node), shared
// by the engine (texelNodeMap, the water graph simulation) and the runtime (samples the bundle's
// texel_nodes image does not cover), so that both pick the same node for every point.
//
// The rule: the node whose compartment is closest to the point (distance to a box node's box,
// else to its centre); ties go to the nearer centre, then to the lower index. A scan of every
// node per point made a graph of the maximum node count (100000) times a texture's entries cost
// ~1e10 distances; NearestNodeIndex answers the same question through a bounding-volume tree in
// about log(nodes) distances per point, with exactly the scan's answer (ties included).
#pragma once

#include "plimsoll_eval/vec.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace plimsoll_eval {

/// A node's compartment as the rule sees it.
struct NodeShape {
    Vec3 centre;  ///< object space, m
    Vec3 box;     ///< box edge lengths (m); unless all are > 0 the node is its centre
    bool isBox() const { return box.x > 0 && box.y > 0 && box.z > 0; }
};

/// Distance from p to the node's compartment: to its box, or to its centre.
inline double nodeDistance(const NodeShape& n, const Vec3& p) {
    const Vec3 q = p - n.centre;
    if (!n.isBox()) return norm(q);
    const Vec3 e{std::max(0.0, std::abs(q.x) - 0.5 * n.box.x),
                 std::max(0.0, std::abs(q.y) - 0.5 * n.box.y),
                 std::max(0.0, std::abs(q.z) - 0.5 * n.box.z)};
    return norm(e);
}

/// The candidate the rule prefers, as (distance, centre distance, index) compared in order.
struct NodeCandidate {
    double distance = std::numeric_limits<double>::infinity();
    double centre = std::numeric_limits<double>::infinity();
    int index = -1;

    /// Whether node `i` at these distances wins over this candidate. The comparisons are the
    /// scan's (`d < best || (d == best && centre < bestCentre)` in index order): a NaN distance
    /// never wins, as in the scan.
    bool beatenBy(double d, double c, int i) const {
        if (d < distance) return true;
        if (!(d == distance)) return false;
        return c < centre || (c == centre && index >= 0 && i < index);
    }
};

/// The rule by a scan of every node (one point, or a reference for the index).
inline int nearestNodeByScan(const std::vector<NodeShape>& nodes, const Vec3& p) {
    NodeCandidate best;
    for (std::size_t j = 0; j < nodes.size(); ++j) {
        const double d = nodeDistance(nodes[j], p), c = norm(nodes[j].centre - p);
        if (best.beatenBy(d, c, static_cast<int>(j))) best = {d, c, static_cast<int>(j)};
    }
    return best.index;
}

/// The rule for many points: a tree of axis-aligned bounds over the nodes' compartments, split at
/// the median of the longest axis, searched nearer child first; a subtree whose bounds lie
/// farther than the best candidate so far cannot hold a better one and is skipped. -1 for no
/// nodes. Building is O(n log n); immutable afterwards, so one index serves many threads.
///
/// Ties cost no more than distinct nodes: nodes of the same shape (same centre and box) answer
/// every point alike, so only the lowest index of each shape enters the tree (100000 nodes at
/// one point are one leaf); and where the best distance is 0 (a point inside boxes that all
/// contain the hull) a subtree whose centres all lie farther than the best centre distance is
/// skipped, since only the centre distance can then decide.
class NearestNodeIndex {
public:
    explicit NearestNodeIndex(std::vector<NodeShape> nodes) : nodes_(std::move(nodes)) {
        order_ = distinctShapes();
        if (order_.empty()) return;
        cells_.resize(1);
        build(0, 0, static_cast<std::uint32_t>(order_.size()));
    }

    /// `examined`, when given, receives the number of nodes whose distance the query computed
    /// (the cost the tree exists to bound).
    int nearest(const Vec3& p, std::size_t* examined = nullptr) const {
        NodeCandidate best;
        if (examined) *examined = 0;
        if (cells_.empty()) return -1;
        std::uint32_t stack[128];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Cell& cell = cells_[stack[--top]];
            if (lowerBound(cell, p) > best.distance) continue;
            if (best.distance == 0 && centreBound(cell, p) > best.centre) continue;
            if (cell.left == 0) {
                if (examined) *examined += cell.end - cell.begin;
                for (std::uint32_t k = cell.begin; k < cell.end; ++k) {
                    const int j = static_cast<int>(order_[k]);
                    const double d = nodeDistance(nodes_[j], p), c = norm(nodes_[j].centre - p);
                    if (best.beatenBy(d, c, j)) best = {d, c, j};
                }
                continue;
            }
            // The nearer child is searched first (pushed last), so the farther one is mostly
            // skipped; between equally near children, the one of nearer centres.
            std::uint32_t nearer = cell.left, farther = cell.left + 1;
            const double dn = lowerBound(cells_[nearer], p), df = lowerBound(cells_[farther], p);
            if (df < dn ||
                (df == dn && centreBound(cells_[farther], p) < centreBound(cells_[nearer], p)))
                std::swap(nearer, farther);
            stack[top++] = farther;
            stack[top++] = nearer;
        }
        return best.index;
    }

    const std::vector<NodeShape>& nodes() const { return nodes_; }

private:
    struct Cell {
        Vec3 lo, hi;                       ///< bounds of every compartment below, padded outwards
        Vec3 centreLo, centreHi;           ///< bounds of their centres, padded outwards
        std::uint32_t begin = 0, end = 0;  ///< the cell's nodes: order_[begin, end)
        std::uint32_t left =
            0;  ///< first of two children (cells_[left], cells_[left + 1]); 0: a leaf
    };
    static constexpr std::uint32_t kLeafSize = 8;

    /// Distance from p to the cell's bounds: no compartment inside is nearer. The bounds are
    /// padded by a relative 1e-9 so that rounding in nodeDistance cannot make a node nearer
    /// than its cell (a skipped tie would change the answer).
    static double lowerBound(const Cell& c, const Vec3& p) {
        const double dx = std::max({0.0, c.lo.x - p.x, p.x - c.hi.x});
        const double dy = std::max({0.0, c.lo.y - p.y, p.y - c.hi.y});
        const double dz = std::max({0.0, c.lo.z - p.z, p.z - c.hi.z});
        return std::sqrt(dx * dx + dy * dy + dz * dz);
    }

    /// Distance from p to the cell's centre bounds: no centre inside is nearer.
    static double centreBound(const Cell& c, const Vec3& p) {
        const double dx = std::max({0.0, c.centreLo.x - p.x, p.x - c.centreHi.x});
        const double dy = std::max({0.0, c.centreLo.y - p.y, p.y - c.centreHi.y});
        const double dz = std::max({0.0, c.centreLo.z - p.z, p.z - c.centreHi.z});
        return std::sqrt(dx * dx + dy * dy + dz * dz);
    }

    /// The indices that enter the tree: of the nodes with the same shape, the lowest (the
    /// scan's choice among them for every point). Shapes holding a NaN are kept as they are
    /// (NaN compares unordered, which a sort cannot take).
    std::vector<std::uint32_t> distinctShapes() const {
        auto key = [&](std::uint32_t i) {
            const NodeShape& n = nodes_[i];
            return std::array<double, 6>{n.centre.x, n.centre.y, n.centre.z,
                                         n.box.x,    n.box.y,    n.box.z};
        };
        std::vector<std::uint32_t> ordered, kept;
        for (std::size_t i = 0; i < nodes_.size(); ++i) {
            const auto k = key(static_cast<std::uint32_t>(i));
            const bool hasNaN =
                std::any_of(k.begin(), k.end(), [](double v) { return std::isnan(v); });
            (hasNaN ? kept : ordered).push_back(static_cast<std::uint32_t>(i));
        }
        std::stable_sort(ordered.begin(), ordered.end(),
                         [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
        for (std::size_t k = 0; k < ordered.size(); ++k) {
            if (k == 0 || key(ordered[k - 1]) < key(ordered[k])) kept.push_back(ordered[k]);
        }
        return kept;
    }

    static double component(const Vec3& v, int axis) {
        return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
    }

    /// Fills cells_[self] for order_[begin, end), then its two children (side by side).
    /// Median splits keep the depth at log2(n / kLeafSize), so the recursion and the query's
    /// stack stay small (2^128 nodes would be needed to overflow it).
    void build(std::uint32_t self, std::uint32_t begin, std::uint32_t end) {
        constexpr double inf = std::numeric_limits<double>::infinity();
        Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
        Vec3 centreLo = lo, centreHi = hi;
        for (std::uint32_t k = begin; k < end; ++k) {
            const NodeShape& n = nodes_[order_[k]];
            const Vec3 half = n.isBox() ? 0.5 * n.box : Vec3{};
            const Vec3 a = n.centre - half, b = n.centre + half;
            lo = {std::min(lo.x, a.x), std::min(lo.y, a.y), std::min(lo.z, a.z)};
            hi = {std::max(hi.x, b.x), std::max(hi.y, b.y), std::max(hi.z, b.z)};
            centreLo = {std::min(centreLo.x, n.centre.x), std::min(centreLo.y, n.centre.y),
                        std::min(centreLo.z, n.centre.z)};
            centreHi = {std::max(centreHi.x, n.centre.x), std::max(centreHi.y, n.centre.y),
                        std::max(centreHi.z, n.centre.z)};
        }
        auto pad = [](double v) { return 1e-9 * (1.0 + std::abs(v)); };
        Cell& cell = cells_[self];
        cell.lo = {lo.x - pad(lo.x), lo.y - pad(lo.y), lo.z - pad(lo.z)};
        cell.hi = {hi.x + pad(hi.x), hi.y + pad(hi.y), hi.z + pad(hi.z)};
        cell.centreLo = {centreLo.x - pad(centreLo.x), centreLo.y - pad(centreLo.y),
                         centreLo.z - pad(centreLo.z)};
        cell.centreHi = {centreHi.x + pad(centreHi.x), centreHi.y + pad(centreHi.y),
                         centreHi.z + pad(centreHi.z)};
        cell.begin = begin;
        cell.end = end;
        if (end - begin <= kLeafSize) return;
        const Vec3 extent = centreHi - centreLo;
        const int axis =
            extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        const std::uint32_t middle = begin + (end - begin) / 2;
        std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                         [&](std::uint32_t a, std::uint32_t b) {
                             return component(nodes_[a].centre, axis) <
                                    component(nodes_[b].centre, axis);
                         });
        const auto left = static_cast<std::uint32_t>(cells_.size());
        cells_.resize(cells_.size() + 2);  // `cell` may dangle from here on
        cells_[self].left = left;
        build(left, begin, middle);
        build(left + 1, middle, end);
    }

    std::vector<NodeShape> nodes_;
    std::vector<std::uint32_t> order_;
    std::vector<Cell> cells_;
};

}  // namespace plimsoll_eval
