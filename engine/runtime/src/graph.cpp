// The water graph's simulation: a port of the engine's WaterGraphSimulation (engine/src/
// graph.cpp, exchange_reference.cpp) with the same step order, random sequence (splitmix64)
// and limits, so the same inputs give the same water (tests/test_runtime_conformance.cpp).
// Box compartments: the engine clips a box mesh against the level plane
// (evaluateBuoyancyExact); this file clips the box's 12 triangles with the same formulas.
#include "plimsoll_runtime/runtime.hpp"

#include "vec.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace plimsoll_runtime {

namespace {

constexpr double kPi = 3.14159265358979323846;

double poiseuilleRate(double dp, double radius, double viscosity, double length) {
    return kPi * dp * std::pow(radius, 4) / (8.0 * viscosity * length);
}

struct Clipped {
    double volume = 0;
    Vec3 moment;
};

/// evaluateBuoyancyExact's addPiece: volume and first moment of the wetted triangle.
void addPiece(const Vec3& a, const Vec3& b, const Vec3& c, double h, Clipped& sums) {
    const Vec3 area = 0.5 * cross(b - a, c - a);
    const Vec3 mids[3] = {0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)};
    double height = 0;
    Vec3 field;
    for (const Vec3& m : mids) {
        const double below = m.y - h;
        height += below;
        field += Vec3{m.x * below, 0.5 * below * (m.y + h), m.z * below};
    }
    height /= 3.0;
    field = (1.0 / 3.0) * field;
    sums.volume += area.y * height;
    sums.moment += area.y * field;
}

void addClipped(const std::array<Vec3, 3>& p, double h, Clipped& sums) {
    std::array<Vec3, 4> polygon;
    int count = 0;
    for (int i = 0; i < 3; ++i) {
        const Vec3& a = p[i];
        const Vec3& b = p[(i + 1) % 3];
        const double da = a.y - h, db = b.y - h;
        if (da <= 0.0) polygon[count++] = a;
        if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
            const Vec3& wet = da < 0.0 ? a : b;
            const Vec3& dry = da < 0.0 ? b : a;
            const double dWet = wet.y - h, dDry = dry.y - h;
            Vec3 crossing = wet + (dWet / (dWet - dDry)) * (dry - wet);
            crossing.y = h;
            polygon[count++] = crossing;
        }
    }
    if (count >= 3) addPiece(polygon[0], polygon[1], polygon[2], h, sums);
    if (count == 4) addPiece(polygon[0], polygon[2], polygon[3], h, sums);
}

/// Volume and first moment (about the box centre, world axes) of the part of a box of edges
/// `size`, centred at the origin and rotated by R, below the plane y = h.
Clipped clipBox(const Vec3& size, const double R[3][3], double h) {
    Vec3 corner[8];
    for (int i = 0; i < 8; ++i) {
        const Vec3 p{(i & 1 ? 0.5 : -0.5) * size.x, (i & 2 ? 0.5 : -0.5) * size.y,
                     (i & 4 ? 0.5 : -0.5) * size.z};
        corner[i] = mul(R, p);
    }
    // Two counter-clockwise (seen from outside) triangles per face.
    static constexpr int kFaces[6][4] = {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3},
                                         {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}};
    Clipped sums;
    for (const auto& f : kFaces) {
        addClipped({corner[f[0]], corner[f[1]], corner[f[2]]}, h, sums);
        addClipped({corner[f[0]], corner[f[2]], corner[f[3]]}, h, sums);
    }
    return sums;
}

}  // namespace

std::uint64_t WaterGraph::random() {
    std::uint64_t z = (rng_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

void WaterGraph::prepare() {
    const std::size_t n = nodes_.size();
    rng_ = settings_.seed;
    links_.assign(n, {});
    radius_.resize(n);
    scaledBox_.assign(n, Vec3{});
    initial_ = entered_ = left_ = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const GraphNode& node = nodes_[i];
        radius_[i] = std::cbrt(3.0 * node.capacity / (4.0 * kPi));
        if (node.isBox()) {
            const double volume = node.box.x * node.box.y * node.box.z;
            scaledBox_[i] = std::cbrt(node.capacity / volume) * node.box;
        }
        initial_ += node.water;
    }
    for (std::size_t p = 0; p < pipes_.size(); ++p) {
        const GraphPipe& pipe = pipes_[p];
        if (!pipe.open) continue;
        const auto a = static_cast<std::uint32_t>(pipe.nodeA);
        const auto b = static_cast<std::uint32_t>(pipe.nodeB);
        if (nodes_[a].sealed || nodes_[b].sealed) continue;
        links_[a].push_back({b, static_cast<std::uint32_t>(p)});
        links_[b].push_back({a, static_cast<std::uint32_t>(p)});
    }
}

double WaterGraph::pipeLength(const GraphPipe& pipe) const {
    if (pipe.length > 0) return pipe.length;
    return norm(nodes_[pipe.nodeA].position - nodes_[pipe.nodeB].position);
}

double WaterGraph::storedWater() const {
    double sum = 0;
    for (const GraphNode& n : nodes_) sum += n.water;
    return sum;
}

void WaterGraph::setWater(std::size_t node, double water) {
    if (node >= nodes_.size()) return;
    GraphNode& n = nodes_[node];
    const double clamped = std::clamp(water, 0.0, n.capacity);
    initial_ += clamped - n.water;
    n.water = clamped;
}

double WaterGraph::nodeHeight(std::size_t node, const double R[3][3]) const {
    const Vec3& p = nodes_[node].position;
    return R[1][0] * p.x + R[1][1] * p.y + R[1][2] * p.z;
}

double WaterGraph::volumeAtLevel(std::size_t node, double offset, const double R[3][3]) const {
    const GraphNode& n = nodes_[node];
    if (!n.isBox()) {
        const double r = radius_[node];
        const double h = std::clamp(offset + r, 0.0, 2.0 * r);
        return std::clamp(kPi * h * h * (3.0 * r - h) / 3.0, 0.0, n.capacity);
    }
    const Clipped c = clipBox(scaledBox_[node], R, offset);
    const double v = std::isfinite(c.volume) && c.volume > 0 ? c.volume : 0.0;
    return std::clamp(v, 0.0, n.capacity);
}

void WaterGraph::levelRange(std::size_t node, const double R[3][3], double& lo, double& hi) const {
    const GraphNode& n = nodes_[node];
    if (!n.isBox()) {
        lo = -radius_[node];
        hi = radius_[node];
        return;
    }
    const Vec3 half = 0.5 * scaledBox_[node];
    const double reach =
        std::abs(R[1][0]) * half.x + std::abs(R[1][1]) * half.y + std::abs(R[1][2]) * half.z;
    lo = -reach;
    hi = reach;
}

double WaterGraph::levelOffsetR(std::size_t node, double water, const double R[3][3]) const {
    const GraphNode& n = nodes_[node];
    double lo = 0, hi = 0;
    levelRange(node, R, lo, hi);
    if (water <= 0) return lo;
    if (water >= n.capacity) return hi;
    for (int it = 0; it < 50 && hi - lo > 1e-12 * (1.0 + std::abs(hi)); ++it) {
        const double mid = 0.5 * (lo + hi);
        (volumeAtLevel(node, mid, R) < water ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double WaterGraph::levelOffset(std::size_t node, double water, const Quat& orientation) const {
    double R[3][3];
    rotationMatrix(orientation, R);
    return levelOffsetR(node, water, R);
}

double WaterGraph::level(std::size_t node, const double R[3][3]) const {
    return nodeHeight(node, R) + levelOffsetR(node, nodes_[node].water, R);
}

NodeInflow WaterGraph::inflowAt(const Pose& pose, const Water& water, double time,
                                const std::vector<double>& surface) const {
    const bool torricelli = settings_.torricelli;
    const double factor = torricelli ? settings_.dischargeCoefficient * std::sqrt(2.0 * settings_.gravity)
                                     : settings_.inflowRate;
    double R[3][3];
    rotationMatrix(pose.orientation, R);
    NodeInflow sums;
    const std::size_t n = nodes_.size();
    sums.inflow.assign(n, 0.0);
    sums.outflow.assign(n, 0.0);
    sums.outsideTop.assign(n, -std::numeric_limits<double>::infinity());
    for (const Exchange& s : exchange_) {
        const Vec3 p = mul(R, s.position) + pose.position;
        const double f = water.heightAt(p.x, p.z, time);
        const double outside = std::max(0.0, f - p.y);
        const double inside = std::max(0.0, surface[s.node] - p.y);
        const double head = outside - inside;
        if (head == 0) continue;
        const double q = torricelli ? factor * s.weight * std::sqrt(std::abs(head))
                                    : factor * s.weight * std::abs(head);
        if (head > 0) {
            sums.inflow[s.node] += q;
            sums.outsideTop[s.node] = std::max(sums.outsideTop[s.node], f);
        } else {
            sums.outflow[s.node] += q;
        }
    }
    return sums;
}

NodeInflow WaterGraph::inflow(const Pose& pose, const Water& water, double time) const {
    double R[3][3];
    rotationMatrix(pose.orientation, R);
    std::vector<double> surface(nodes_.size(), -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        if (nodes_[i].sealed || nodes_[i].water <= 0) continue;
        surface[i] = pose.position.y + level(i, R);
    }
    return inflowAt(pose, water, time, surface);
}

bool WaterGraph::exchange(const Pose& pose, const Water& water, double time, double dt) {
    if (exchange_.empty()) return false;
    return applyExchange(pose, dt, inflow(pose, water, time));
}

bool WaterGraph::applyExchange(const Pose& pose, double dt, const NodeInflow& rates) {
    const std::size_t n = nodes_.size();
    double R[3][3];
    rotationMatrix(pose.orientation, R);
    std::vector<double> levels(n);
    for (std::size_t i = 0; i < n; ++i) levels[i] = level(i, R);
    bool moved = false;
    for (std::size_t i = 0; i < n; ++i) {
        GraphNode& node = nodes_[i];
        double gain = rates.inflow[i] * dt, loss = rates.outflow[i] * dt;
        if (gain == 0 && loss == 0) continue;
        // A full node passes what the outside pushes in on to the nodes it joins.
        double excess = node.water + gain - loss - node.capacity;
        while (excess > 0) {
            const Path path = findPath(static_cast<int>(i), R, levels,
                                       rates.outsideTop[i] - pose.position.y);
            if (path.node < 0) break;
            GraphNode& target = nodes_[path.node];
            const double before = target.water;
            target.water = std::min(target.capacity, before + excess);
            const double passed = target.water - before;
            if (!(passed > 0)) break;
            excess -= passed;
            entered_ += passed;
            levels[path.node] = level(path.node, R);
            moved = true;
        }
        if (node.water + gain - loss > node.capacity) gain = node.capacity - node.water + loss;
        if (node.water + gain - loss < 0) loss = node.water + gain;
        const double before = node.water;
        node.water = std::clamp(before + gain - loss, 0.0, node.capacity);
        const double change = node.water - before;
        const double booked = gain - loss;
        if (change != booked) {
            if (change > booked) gain += change - booked;
            else loss += booked - change;
        }
        entered_ += gain;
        left_ += loss;
        moved = moved || change != 0 || gain != 0;
    }
    return moved;
}

WaterGraph::Path WaterGraph::findPath(int source, const double R[3][3],
                                      const std::vector<double>& levels, double sourceLevel) {
    // The paper's Algorithm 1 with an explicit stack (engine: WaterGraphSimulation::findPath).
    Path none;
    if (nodes_[source].sealed) return none;
    std::vector<char> visited(nodes_.size(), 0);
    visited[source] = 1;
    struct Frame {
        int node;
        std::vector<Link> order;
        std::size_t next;
        double radius, length;
    };
    auto shuffled = [&](int node) {
        std::vector<Link> order = links_[node];
        for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[randomBelow(i)]);
        return order;
    };
    std::vector<Frame> stack;
    stack.push_back({source, shuffled(source), 0, std::numeric_limits<double>::infinity(), 0.0});
    while (!stack.empty()) {
        Frame& top = stack.back();
        if (top.next == top.order.size()) {
            stack.pop_back();
            continue;
        }
        const Link link = top.order[top.next++];
        const int m = static_cast<int>(link.node);
        if (visited[m]) continue;
        visited[m] = 1;
        double lo = 0, hi = 0;
        levelRange(m, R, lo, hi);
        if (nodeHeight(m, R) + lo > sourceLevel) continue;  // an energy barrier
        const GraphPipe& pipe = pipes_[link.pipe];
        const double radius = std::min(top.radius, pipe.radius);
        const double length = top.length + pipeLength(pipe);
        const GraphNode& node = nodes_[m];
        const bool full = node.water >= node.capacity;
        if (!full && levels[m] < sourceLevel) return {m, radius, length};
        if (full) stack.push_back({m, shuffled(m), 0, radius, length});
    }
    return none;
}

bool WaterGraph::flowPoiseuille(const double R[3][3], double dt) {
    const std::size_t n = nodes_.size();
    std::vector<double> levels(n);
    for (std::size_t i = 0; i < n; ++i) levels[i] = level(i, R);
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[randomBelow(i)]);
    const double rhoG = settings_.density * settings_.gravity;
    bool moved = false;
    for (std::size_t source : order) {
        if (nodes_[source].water <= 0) continue;
        const Path path = findPath(static_cast<int>(source), R, levels, levels[source]);
        if (path.node < 0) continue;
        const auto d = static_cast<std::size_t>(path.node);
        GraphNode& a = nodes_[source];
        GraphNode& b = nodes_[d];
        const double dh = levels[source] - levels[d];
        const double rate = poiseuilleRate(rhoG * dh, path.radius, settings_.viscosity,
                                           std::max(path.length, 1e-9));
        const double ha = nodeHeight(source, R), hb = nodeHeight(d, R);
        const double total = a.water + b.water;
        double lo = levels[d], hi = levels[source];
        for (int it = 0; it < 60 && hi - lo > 1e-13 * (1.0 + std::abs(hi)); ++it) {
            const double mid = 0.5 * (lo + hi);
            const double v = volumeAtLevel(source, mid - ha, R) + volumeAtLevel(d, mid - hb, R);
            (v < total ? lo : hi) = mid;
        }
        const double equalise = std::max(0.0, a.water - volumeAtLevel(source, hi - ha, R));
        double amount = std::min({rate * dt, equalise, a.water, b.capacity - b.water});
        if (!(amount > 0)) continue;
        const double before = b.water;
        b.water = std::min(b.capacity, b.water + amount);
        amount = b.water - before;
        a.water = std::max(0.0, a.water - amount);
        levels[source] = level(source, R);
        levels[d] = level(d, R);
        moved = true;
    }
    return moved;
}

bool WaterGraph::flowDiffusion(double dt) {
    const std::size_t count = pipes_.size();
    std::vector<std::size_t> order(count);
    for (std::size_t i = 0; i < count; ++i) order[i] = i;
    for (std::size_t i = count; i > 1; --i) std::swap(order[i - 1], order[randomBelow(i)]);
    bool moved = false;
    for (std::size_t p : order) {
        const GraphPipe& pipe = pipes_[p];
        if (!pipe.open) continue;
        if (nodes_[pipe.nodeA].sealed || nodes_[pipe.nodeB].sealed) continue;
        GraphNode* full = &nodes_[pipe.nodeA];
        GraphNode* empty = &nodes_[pipe.nodeB];
        double ca = full->water / full->capacity, cb = empty->water / empty->capacity;
        if (ca < cb) {
            std::swap(full, empty);
            std::swap(ca, cb);
        }
        if (!(ca > cb)) continue;
        const double rate = poiseuilleRate(settings_.diffusionPressure * (ca - cb), pipe.radius,
                                           settings_.viscosity, std::max(pipeLength(pipe), 1e-9));
        const double equalise = (ca - cb) / (1.0 / full->capacity + 1.0 / empty->capacity);
        double amount = std::min({rate * dt, equalise, full->water, empty->capacity - empty->water});
        if (!(amount > 0)) continue;
        const double before = empty->water;
        empty->water = std::min(empty->capacity, empty->water + amount);
        amount = empty->water - before;
        full->water = std::max(0.0, full->water - amount);
        moved = true;
    }
    return moved;
}

bool WaterGraph::flowInside(const Quat& orientation, double dt) {
    double R[3][3];
    rotationMatrix(orientation, R);
    return settings_.diffusion ? flowDiffusion(dt) : flowPoiseuille(R, dt);
}

bool WaterGraph::step(const Pose& pose, const Water& water, double time, double dt) {
    const bool exchanged = exchange(pose, water, time, dt);
    const bool flowed = flowInside(pose.orientation, dt);
    return exchanged || flowed;
}

Vec3 WaterGraph::waterCentroid(std::size_t node, double water, const double R[3][3]) const {
    const GraphNode& n = nodes_[node];
    if (!settings_.freeSurface || water >= n.capacity) return n.position;
    const Vec3 up{R[1][0], R[1][1], R[1][2]};  // world up in object axes
    if (!n.isBox()) {
        const double r = radius_[node];
        const double h = std::clamp(levelOffsetR(node, water, R) + r, 0.0, 2.0 * r);
        const double below = h > 0 ? 3.0 * (2.0 * r - h) * (2.0 * r - h) / (4.0 * (3.0 * r - h)) : r;
        return n.position - below * up;
    }
    const Clipped c = clipBox(scaledBox_[node], R, levelOffsetR(node, water, R));
    if (!(c.volume > 0) || !std::isfinite(c.volume)) return n.position;
    const Vec3 centroid{c.moment.x / c.volume, c.moment.y / c.volume, c.moment.z / c.volume};
    return n.position + mulT(R, centroid);
}

MassProperties WaterGraph::waterMass(const Quat& orientation) const {
    double R[3][3];
    rotationMatrix(orientation, R);
    MassProperties p;
    Vec3 moment;
    std::vector<std::pair<double, Vec3>> points;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const double w = nodes_[i].water;
        if (!(w > 0)) continue;
        const double m = settings_.density * w;
        const Vec3 c = waterCentroid(i, w, R);
        points.emplace_back(m, c);
        p.mass += m;
        p.volume += w;
        moment += m * c;
    }
    if (!(p.mass > 0)) return p;
    p.centerOfMass = (1.0 / p.mass) * moment;
    for (const auto& [m, c] : points) {
        const Vec3 d = c - p.centerOfMass;
        const double dv[3] = {d.x, d.y, d.z};
        for (int r = 0; r < 3; ++r) {
            for (int k = 0; k < 3; ++k) {
                p.inertia[r][k] += m * ((r == k ? dot(d, d) : 0.0) - dv[r] * dv[k]);
            }
        }
    }
    return p;
}

}  // namespace plimsoll_runtime
