// Water graph: validation and simulation (graph.h; paper section 4, DESIGN.md "Water graph").
//
// Step order, each step of dt (World steps it once a frame):
//  1. exchange through the surface (paper 4.2; the per-texel pass is kernels/graph.cl or its
//     C++ reference, exchange_reference.cpp): every permeable texel i feeds its node n; with
//     d_out = max(0, f(x, z) - y_i) the outside depth and d_in = max(0, level_n - y_i) the
//     inside head, h = d_out - d_in drives q_i = rate k_i |A_i| h (or Torricelli's
//     C_d k_i |A_i| sqrt(2 g |h|)); positive flows in, negative out (water leaves through
//     texels above the outside water and below the inside level). A full node passes what
//     still pushes in on to a node it reaches through full nodes (as findDischargeNode
//     searches, with the outside surface as the source's level). Per node the gross inflow
//     and outflow are limited so the node stays in [0, capacity], and the amounts actually
//     moved are what the bookkeeping adds: entered + initial = stored + left, to rounding.
//  2. flow inside: every node in random order asks findDischargeNode (paper Algorithm 1) for a
//     node to discharge into and sends it Q dt, Q = pi rho g dh r^4 / (8 mu L) (paper eq. 14;
//     r the narrowest pipe and L the length of the path, dh the difference of water levels),
//     at most the amount that brings both levels together: two connected nodes never swap
//     which one is higher, so nothing oscillates. Diffusion mode: along every open pipe from
//     the fuller node to the emptier, at most until both are equally full.
// The water's mass properties (paper eqs. 15-17) are those of point masses rho v_n at the nodes,
// or, with the free-surface model, at the centroid of the water lying at each node's lowest side.
#include "plimsoll/graph.h"

#include "plimsoll/bake.h"
#include "plimsoll/buoyancy.h"
#include "plimsoll/primitives.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace plimsoll {

// ---------------------------------------------------------------------------------------
// Graph

int WaterGraph::indexOf(const std::string& id) const {
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        if (nodes[i].id == id) return static_cast<int>(i);
    }
    return -1;
}

double WaterGraph::totalCapacity() const {
    double sum = 0;
    for (const GraphNode& n : nodes) sum += n.capacity;
    return sum;
}

double WaterGraph::totalWater() const {
    double sum = 0;
    for (const GraphNode& n : nodes) sum += n.water;
    return sum;
}

double WaterGraph::pipeLength(const GraphPipe& pipe) const {
    if (pipe.length > 0) return pipe.length;
    const int a = indexOf(pipe.a), b = indexOf(pipe.b);
    if (a < 0 || b < 0) return 0;
    return (nodes[a].position - nodes[b].position).norm();
}

// ---------------------------------------------------------------------------------------
// Validation

const char* graphProblemCode(GraphProblemKind kind) {
    switch (kind) {
        case GraphProblemKind::Empty: return "empty-graph";
        case GraphProblemKind::DuplicateId: return "duplicate-id";
        case GraphProblemKind::BadCapacity: return "bad-capacity";
        case GraphProblemKind::WaterOutOfRange: return "water-out-of-range";
        case GraphProblemKind::DanglingPipe: return "dangling-pipe";
        case GraphProblemKind::SelfLoop: return "self-loop";
        case GraphProblemKind::BadPipe: return "bad-pipe";
        case GraphProblemKind::NodeOutsideMesh: return "node-outside-mesh";
        case GraphProblemKind::Disconnected: return "disconnected";
    }
    return "unknown";
}

bool GraphReport::has(GraphProblemKind kind) const {
    return std::any_of(problems.begin(), problems.end(),
                       [kind](const GraphProblem& p) { return p.kind == kind; });
}

bool GraphReport::hasErrors() const {
    return std::any_of(problems.begin(), problems.end(),
                       [](const GraphProblem& p) { return p.error; });
}

std::string GraphReport::format() const {
    std::string out;
    for (bool errors : {true, false}) {
        for (const GraphProblem& p : problems) {
            if (p.error != errors) continue;
            if (!out.empty()) out += '\n';
            out += (source.empty() ? std::string() : source + ": ") +
                   (p.error ? "error [" : "warning [") + graphProblemCode(p.kind) + "]: " +
                   p.message;
        }
    }
    return out;
}

double windingNumber(const TriangleMesh& mesh, const Eigen::Vector3d& point) {
    // Sum of the signed solid angles of the triangles seen from the point (Van Oosterom and
    // Strackee 1983), over 4 pi.
    double total = 0;
    for (const Triangle& t : mesh.triangles) {
        const Eigen::Vector3d a = mesh.positions[t[0]] - point;
        const Eigen::Vector3d b = mesh.positions[t[1]] - point;
        const Eigen::Vector3d c = mesh.positions[t[2]] - point;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        const double numerator = a.dot(b.cross(c));
        const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        total += 2.0 * std::atan2(numerator, denominator);
    }
    return total / (4.0 * std::numbers::pi);
}

GraphReport validateGraph(const WaterGraph& graph, const TriangleMesh* mesh,
                          const std::string& source) {
    GraphReport report;
    report.source = source;
    auto add = [&](GraphProblemKind kind, bool error, std::string message) {
        report.problems.push_back({kind, error, std::move(message)});
    };
    if (graph.nodes.empty()) add(GraphProblemKind::Empty, true, "the graph has no nodes");
    for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
        const GraphNode& n = graph.nodes[i];
        const std::string label = "node " + std::to_string(i) + " '" + n.id + "'";
        if (n.id.empty()) {
            add(GraphProblemKind::DuplicateId, true, "node " + std::to_string(i) + " has no id");
        }
        for (std::size_t j = 0; j < i; ++j) {
            if (!n.id.empty() && graph.nodes[j].id == n.id) {
                add(GraphProblemKind::DuplicateId, true,
                    label + ": id already used by node " + std::to_string(j));
                break;
            }
        }
        if (!(n.capacity > 0) || !std::isfinite(n.capacity)) {
            std::ostringstream m;
            m << label << ": capacity " << n.capacity << " m^3 must be > 0";
            add(GraphProblemKind::BadCapacity, true, m.str());
        } else if (!(n.water >= 0) || n.water > n.capacity) {
            std::ostringstream m;
            m << label << ": water " << n.water << " m^3 must be in 0.." << n.capacity;
            add(GraphProblemKind::WaterOutOfRange, true, m.str());
        }
        if (!n.position.allFinite()) {
            add(GraphProblemKind::BadCapacity, true, label + ": position is not finite");
        }
        if (!n.boxSize.isZero(0.0) && !(n.boxSize.minCoeff() > 0 && n.boxSize.allFinite())) {
            add(GraphProblemKind::BadCapacity, true, label + ": box edges must all be > 0");
        }
    }
    for (std::size_t i = 0; i < graph.pipes.size(); ++i) {
        const GraphPipe& p = graph.pipes[i];
        const std::string label = "pipe " + std::to_string(i) + " ('" + p.a + "' - '" + p.b + "')";
        const int a = graph.indexOf(p.a), b = graph.indexOf(p.b);
        if (a < 0 || b < 0) {
            add(GraphProblemKind::DanglingPipe, true,
                label + ": no node '" + (a < 0 ? p.a : p.b) + "'");
        } else if (a == b) {
            add(GraphProblemKind::SelfLoop, true, label + ": joins a node to itself");
        }
        if (!(p.radius > 0) || !std::isfinite(p.radius) || !(p.length >= 0) ||
            !std::isfinite(p.length)) {
            std::ostringstream m;
            m << label << ": radius " << p.radius << " m must be > 0 and length " << p.length
              << " m >= 0";
            add(GraphProblemKind::BadPipe, true, m.str());
        } else if (a >= 0 && b >= 0 && a != b && !(graph.pipeLength(p) > 0)) {
            add(GraphProblemKind::BadPipe, true,
                label + ": its nodes coincide, so it needs a length > 0");
        }
    }
    // Groups of nodes joined by open pipes (union-find).
    if (!graph.nodes.empty()) {
        std::vector<int> parent(graph.nodes.size());
        for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
        auto root = [&](int i) {
            while (parent[i] != i) i = parent[i] = parent[parent[i]];
            return i;
        };
        for (const GraphPipe& p : graph.pipes) {
            const int a = graph.indexOf(p.a), b = graph.indexOf(p.b);
            if (a >= 0 && b >= 0 && p.open) parent[root(a)] = root(b);
        }
        std::size_t groups = 0;
        for (std::size_t i = 0; i < parent.size(); ++i) groups += root(static_cast<int>(i)) == static_cast<int>(i);
        if (groups > 1) {
            add(GraphProblemKind::Disconnected, false,
                std::to_string(groups) + " groups of nodes that no open pipe joins");
        }
    }
    if (mesh && !mesh->triangles.empty()) {
        for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
            const GraphNode& n = graph.nodes[i];
            if (!n.position.allFinite()) continue;
            const double w = windingNumber(*mesh, n.position);
            if (w < 0.5) {
                std::ostringstream m;
                m << "node " << i << " '" << n.id << "' at (" << n.position.x() << ", "
                  << n.position.y() << ", " << n.position.z() << ") lies outside the mesh";
                add(GraphProblemKind::NodeOutsideMesh, false, m.str());
            }
        }
    }
    return report;
}

// ---------------------------------------------------------------------------------------
// Simulation

const char* inflowModelName(InflowModel model) {
    return model == InflowModel::Torricelli ? "torricelli" : "linear";
}

const char* flowModelName(FlowMode mode) {
    return mode == FlowMode::Diffusion ? "diffusion" : "poiseuille";
}

double WaterGraphSimulation::poiseuilleRate(double dp, double radius, double viscosity,
                                            double length) {
    return std::numbers::pi * dp * std::pow(radius, 4) / (8.0 * viscosity * length);
}

namespace {

/// Distance from p to node n's compartment: to its box, or to its centre.
double distanceToNode(const GraphNode& n, const Eigen::Vector3d& p) {
    if (!n.isBox()) return (p - n.position).norm();
    const Eigen::Vector3d d =
        ((p - n.position).cwiseAbs() - 0.5 * n.boxSize).cwiseMax(0.0);
    return d.norm();
}

/// Edge lengths of node n's box scaled to hold exactly its capacity.
Eigen::Vector3d scaledBox(const GraphNode& n) {
    const double volume = n.boxSize.prod();
    return n.boxSize * std::cbrt(n.capacity / volume);
}

}  // namespace

int nearestNode(const WaterGraph& graph, const Eigen::Vector3d& point) {
    int nearest = -1;
    double best = std::numeric_limits<double>::infinity();
    double bestCentre = best;
    for (std::size_t j = 0; j < graph.nodes.size(); ++j) {
        const double d = distanceToNode(graph.nodes[j], point);
        const double centre = (graph.nodes[j].position - point).norm();
        if (d < best || (d == best && centre < bestCentre)) {
            best = d;
            bestCentre = centre;
            nearest = static_cast<int>(j);
        }
    }
    return nearest;
}

std::vector<std::int32_t> texelNodeMap(const WaterGraph& graph, const SurfaceTextures& textures) {
    std::vector<std::int32_t> nodes(textures.position.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i] = nearestNode(graph, textures.position[i]);
    return nodes;
}

Result<WaterGraphSimulation> WaterGraphSimulation::create(const WaterGraph& graph,
                                                          const SurfaceTextures& textures,
                                                          const std::vector<double>& permeability,
                                                          const GraphSettings& settings) {
    const GraphReport report = validateGraph(graph);
    if (report.hasErrors()) return makeError(report.format());
    if (!permeability.empty() && permeability.size() != textures.coveredCount()) {
        return makeError("water graph: " + std::to_string(permeability.size()) +
                         " permeability values for " + std::to_string(textures.coveredCount()) +
                         " texel entries");
    }
    if (settings.flow == FlowMode::Poiseuille && !(settings.viscosity > 0)) {
        return makeError("water graph: Poiseuille flow needs a viscosity > 0");
    }
    WaterGraphSimulation sim;
    sim.graph_ = graph;
    sim.settings_ = settings;
    sim.rng_ = settings.seed;
    const std::size_t n = graph.nodes.size();
    sim.links_.resize(n);
    sim.radius_.resize(n);
    sim.boxes_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const GraphNode& node = graph.nodes[i];
        sim.radius_[i] = std::cbrt(3.0 * node.capacity / (4.0 * std::numbers::pi));
        if (node.isBox()) sim.boxes_[i] = makeBox(scaledBox(node));
        sim.totals_.initial += node.water;
    }
    for (std::size_t p = 0; p < graph.pipes.size(); ++p) {
        const GraphPipe& pipe = graph.pipes[p];
        if (!pipe.open) continue;
        const auto a = static_cast<std::uint32_t>(graph.indexOf(pipe.a));
        const auto b = static_cast<std::uint32_t>(graph.indexOf(pipe.b));
        if (graph.nodes[a].sealed || graph.nodes[b].sealed) continue;
        sim.links_[a].push_back({b, static_cast<std::uint32_t>(p)});
        sim.links_[b].push_back({a, static_cast<std::uint32_t>(p)});
    }
    for (std::size_t i = 0; i < permeability.size(); ++i) {
        const double k = std::clamp(permeability[i], 0.0, 1.0);
        if (!(k > 0)) continue;
        ExchangeSample s;
        s.position = textures.position[i];
        s.weight = k * textures.area[i];
        s.node = static_cast<std::uint32_t>(nearestNode(graph, s.position));
        // A sealed node exchanges nothing: its texels are left out.
        if (!graph.nodes[s.node].sealed) sim.samples_.push_back(s);
    }
    return sim;
}

std::uint64_t WaterGraphSimulation::random() {
    // splitmix64: the same sequence on every platform and standard library.
    std::uint64_t z = (rng_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double WaterGraphSimulation::storedWater() const { return graph_.totalWater(); }

double WaterGraphSimulation::conservationError() const {
    const double in = totals_.entered + totals_.initial;
    const double balance = in - totals_.left - storedWater();
    return std::abs(balance) / std::max(in, 1e-300);
}

void WaterGraphSimulation::setWater(std::size_t node, double water) {
    GraphNode& n = graph_.nodes.at(node);
    const double clamped = std::clamp(water, 0.0, n.capacity);
    totals_.initial += clamped - n.water;
    n.water = clamped;
}

double WaterGraphSimulation::nodeHeight(std::size_t node, const Eigen::Matrix3d& rotation) const {
    return rotation.row(1).dot(graph_.nodes[node].position);
}

double WaterGraphSimulation::volumeAtLevel(std::size_t node, double offset,
                                           const Eigen::Matrix3d& rotation) const {
    const GraphNode& n = graph_.nodes[node];
    if (!n.isBox()) {
        const double r = radius_[node];
        const double h = std::clamp(offset + r, 0.0, 2.0 * r);
        return std::clamp(std::numbers::pi * h * h * (3.0 * r - h) / 3.0, 0.0, n.capacity);
    }
    BodyFrame frame;
    frame.pose.rotation = rotation;
    const BuoyancyResult r = evaluateBuoyancyExact(boxes_[node], frame, offset, FluidSettings{});
    return std::clamp(r.submergedVolume, 0.0, n.capacity);
}

/// Lowest and highest world offsets of the node's compartment about its position.
static std::pair<double, double> levelRange(const GraphNode& n, double sphereRadius,
                                            const Eigen::Matrix3d& rotation) {
    if (!n.isBox()) return {-sphereRadius, sphereRadius};
    const Eigen::Vector3d half = 0.5 * scaledBox(n);
    const double reach = rotation.row(1).cwiseAbs().dot(half.transpose().eval());
    return {-reach, reach};
}

double WaterGraphSimulation::levelOffset(std::size_t node, double water,
                                         const Eigen::Matrix3d& rotation) const {
    const GraphNode& n = graph_.nodes[node];
    auto [lo, hi] = levelRange(n, radius_[node], rotation);
    if (water <= 0) return lo;
    if (water >= n.capacity) return hi;
    for (int it = 0; it < 50 && hi - lo > 1e-12 * (1.0 + std::abs(hi)); ++it) {
        const double mid = 0.5 * (lo + hi);
        (volumeAtLevel(node, mid, rotation) < water ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double WaterGraphSimulation::level(std::size_t node, const Eigen::Matrix3d& rotation) const {
    return nodeHeight(node, rotation) + levelOffset(node, graph_.nodes[node].water, rotation);
}

ExchangeFrame WaterGraphSimulation::exchangeFrame(const Pose& pose, double time) {
    // World height of every node's water surface (a node with no water has none).
    const std::size_t n = graph_.nodes.size();
    scratchSurface_.assign(n, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < n; ++i) {
        if (graph_.nodes[i].sealed || graph_.nodes[i].water <= 0) continue;
        scratchSurface_[i] = pose.translation.y() + level(i, pose.rotation);
    }
    ExchangeFrame frame;
    frame.pose = pose;
    frame.time = time;
    frame.nodeSurface = scratchSurface_;
    frame.torricelli = settings_.inflow == InflowModel::Torricelli;
    frame.factor = frame.torricelli
                       ? settings_.dischargeCoefficient * std::sqrt(2.0 * settings_.gravity)
                       : settings_.inflowRate;
    return frame;
}

bool WaterGraphSimulation::exchange(const Pose& pose, const WaterModel& water, double time,
                                    double dt) {
    if (samples_.empty()) return false;
    const ExchangeFrame frame = exchangeFrame(pose, time);
    evaluateExchangeReference(samples_, graph_.nodes.size(), frame, water, scratchSums_);
    return applyExchange(pose, dt, scratchSums_);
}

bool WaterGraphSimulation::applyExchange(const Pose& pose, double dt, const ExchangeSums& rates) {
    const std::size_t n = graph_.nodes.size();
    if (samples_.empty() || rates.inflow.size() != n) return false;
    // Every node's level relative to the body's origin, for passing water on.
    std::vector<double>& levels = scratchLevels_;
    levels.resize(n);
    for (std::size_t i = 0; i < n; ++i) levels[i] = level(i, pose.rotation);
    bool moved = false;
    for (std::size_t i = 0; i < n; ++i) {
        GraphNode& node = graph_.nodes[i];
        double gain = rates.inflow[i] * dt, loss = rates.outflow[i] * dt;
        if (gain == 0 && loss == 0) continue;
        // A full node passes what the outside pushes in on to the nodes it joins (through
        // full nodes, as in findDischargeNode), as far as the outside surface reaches: water
        // that enters a flooded stern compartment goes on into the holds.
        double excess = node.water + gain - loss - node.capacity;
        while (excess > 0) {
            const Path path = findPath(static_cast<int>(i), pose.rotation, levels,
                                       rates.outsideTop[i] - pose.translation.y());
            if (path.node < 0) break;
            GraphNode& target = graph_.nodes[path.node];
            const double before = target.water;
            target.water = std::min(target.capacity, before + excess);
            const double passed = target.water - before;
            if (!(passed > 0)) break;
            excess -= passed;
            totals_.entered += passed;
            levels[path.node] = level(path.node, pose.rotation);
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
            if (change > booked) gain += change - booked;
            else loss += booked - change;
        }
        totals_.entered += gain;
        totals_.left += loss;
        moved = moved || change != 0 || gain != 0;
    }
    return moved;
}

std::uint64_t WaterGraphSimulation::randomBelow(std::uint64_t n) { return random() % n; }

int WaterGraphSimulation::findDischargeNode(int source, const Eigen::Matrix3d& rotation) {
    if (graph_.nodes[source].water <= 0) return -1;
    std::vector<double> levels(graph_.nodes.size());
    for (std::size_t i = 0; i < levels.size(); ++i) levels[i] = level(i, rotation);
    return findPath(source, rotation, levels, levels[source]).node;
}

WaterGraphSimulation::Path WaterGraphSimulation::findPath(int source,
                                                          const Eigen::Matrix3d& rotation,
                                                          const std::vector<double>& levels,
                                                          double sourceLevel) {
    // Paper Algorithm 1, iteratively (an explicit stack) so deep graphs cannot overflow.
    // sourceLevel: the height the water comes from (the source's level, or the outside
    // surface pushing through a full node), relative to the body's origin.
    Path none;
    const GraphNode& s = graph_.nodes[source];
    if (s.sealed) return none;
    std::vector<char> visited(graph_.nodes.size(), 0);
    visited[source] = 1;
    struct Frame {
        int node;
        std::vector<Link> order;
        std::size_t next;
        double radius, length;
    };
    auto shuffled = [&](int node) {
        std::vector<Link> order = links_[node];
        for (std::size_t i = order.size(); i > 1; --i) {
            std::swap(order[i - 1], order[randomBelow(i)]);
        }
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
        // A node higher than the source (its lowest point above the source's water level) is
        // an energy barrier: nothing passes through it.
        const GraphNode& candidate = graph_.nodes[m];
        const double bottom =
            nodeHeight(m, rotation) + levelRange(candidate, radius_[m], rotation).first;
        if (bottom > sourceLevel) continue;
        const GraphPipe& pipe = graph_.pipes[link.pipe];
        const double radius = std::min(top.radius, pipe.radius);
        const double length = top.length + graph_.pipeLength(pipe);
        const GraphNode& node = graph_.nodes[m];
        const bool full = node.water >= node.capacity;
        if (!full && levels[m] < sourceLevel) return {m, radius, length};
        // Water passes on only through a full node (paper figure 7: A through B to C).
        if (full) stack.push_back({m, shuffled(m), 0, radius, length});
    }
    return none;
}

bool WaterGraphSimulation::flowPoiseuille(const Eigen::Matrix3d& rotation, double dt) {
    const std::size_t n = graph_.nodes.size();
    std::vector<double> levels(n);
    for (std::size_t i = 0; i < n; ++i) levels[i] = level(i, rotation);
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[randomBelow(i)]);
    const double rhoG = settings_.density * settings_.gravity;
    bool moved = false;
    for (std::size_t source : order) {
        if (graph_.nodes[source].water <= 0) continue;
        const Path path = findPath(static_cast<int>(source), rotation, levels, levels[source]);
        if (path.node < 0) continue;
        const auto d = static_cast<std::size_t>(path.node);
        GraphNode& a = graph_.nodes[source];
        GraphNode& b = graph_.nodes[d];
        const double dh = levels[source] - levels[d];
        const double rate =
            poiseuilleRate(rhoG * dh, path.radius, settings_.viscosity, std::max(path.length, 1e-9));
        // The most that can move without the levels crossing: both at a common level L with
        // vol_a(L) + vol_b(L) = water_a + water_b (bisection; the bracket's upper end keeps
        // the move on the safe side).
        const double ha = nodeHeight(source, rotation), hb = nodeHeight(d, rotation);
        const double total = a.water + b.water;
        double lo = levels[d], hi = levels[source];
        for (int it = 0; it < 60 && hi - lo > 1e-13 * (1.0 + std::abs(hi)); ++it) {
            const double mid = 0.5 * (lo + hi);
            const double v = volumeAtLevel(source, mid - ha, rotation) +
                             volumeAtLevel(d, mid - hb, rotation);
            (v < total ? lo : hi) = mid;
        }
        const double equalise = std::max(0.0, a.water - volumeAtLevel(source, hi - ha, rotation));
        double amount = std::min({rate * dt, equalise, a.water, b.capacity - b.water});
        if (!(amount > 0)) continue;
        const double before = b.water;
        b.water = std::min(b.capacity, b.water + amount);
        amount = b.water - before;
        a.water = std::max(0.0, a.water - amount);
        totals_.moved += amount;
        levels[source] = level(source, rotation);
        levels[d] = level(d, rotation);
        moved = true;
    }
    return moved;
}

bool WaterGraphSimulation::flowDiffusion(double dt) {
    const std::size_t count = graph_.pipes.size();
    std::vector<std::size_t> order(count);
    for (std::size_t i = 0; i < count; ++i) order[i] = i;
    for (std::size_t i = count; i > 1; --i) std::swap(order[i - 1], order[randomBelow(i)]);
    bool moved = false;
    for (std::size_t p : order) {
        const GraphPipe& pipe = graph_.pipes[p];
        if (!pipe.open) continue;
        int a = graph_.indexOf(pipe.a), b = graph_.indexOf(pipe.b);
        if (graph_.nodes[a].sealed || graph_.nodes[b].sealed) continue;
        GraphNode* full = &graph_.nodes[a];
        GraphNode* empty = &graph_.nodes[b];
        double ca = full->water / full->capacity, cb = empty->water / empty->capacity;
        if (ca < cb) {
            std::swap(full, empty);
            std::swap(ca, cb);
        }
        if (!(ca > cb)) continue;
        const double rate = poiseuilleRate(settings_.diffusionPressure * (ca - cb), pipe.radius,
                                           settings_.viscosity,
                                           std::max(graph_.pipeLength(pipe), 1e-9));
        // At most until both are equally full (no overshoot).
        const double equalise = (ca - cb) / (1.0 / full->capacity + 1.0 / empty->capacity);
        double amount = std::min({rate * dt, equalise, full->water, empty->capacity - empty->water});
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

bool WaterGraphSimulation::flowInside(const Eigen::Matrix3d& rotation, double dt) {
    return settings_.flow == FlowMode::Diffusion ? flowDiffusion(dt)
                                                 : flowPoiseuille(rotation, dt);
}

bool WaterGraphSimulation::step(const Pose& pose, const WaterModel& water, double time,
                                double dt) {
    const bool exchanged = exchange(pose, water, time, dt);
    const bool flowed = flowInside(pose.rotation, dt);
    return exchanged || flowed;
}

Eigen::Vector3d WaterGraphSimulation::waterCentroid(std::size_t node, double water,
                                                    const Eigen::Matrix3d& rotation) const {
    const GraphNode& n = graph_.nodes[node];
    if (!settings_.freeSurface || water >= n.capacity) return n.position;
    if (!n.isBox()) {
        // Sphere cap of height h at the sphere's lowest side: centroid 3 (2R - h)^2 /
        // (4 (3R - h)) below the centre, along gravity.
        const double r = radius_[node];
        const double h = std::clamp(levelOffset(node, water, rotation) + r, 0.0, 2.0 * r);
        const double below = h > 0 ? 3.0 * (2.0 * r - h) * (2.0 * r - h) / (4.0 * (3.0 * r - h)) : r;
        return n.position - below * rotation.row(1).transpose();
    }
    BodyFrame frame;
    frame.pose.rotation = rotation;
    const BuoyancyResult r = evaluateBuoyancyExact(boxes_[node], frame,
                                                   levelOffset(node, water, rotation),
                                                   FluidSettings{});
    if (!(r.submergedVolume > 0)) return n.position;
    // Back to object space (the frame's translation is zero).
    return n.position + rotation.transpose() * r.centerOfBuoyancy;
}

MassProperties WaterGraphSimulation::waterMassProperties(const Eigen::Matrix3d& rotation) const {
    MassProperties p;
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
    std::vector<std::pair<double, Eigen::Vector3d>> points;
    for (std::size_t i = 0; i < graph_.nodes.size(); ++i) {
        const double w = graph_.nodes[i].water;
        if (!(w > 0)) continue;
        const double m = settings_.density * w;          // paper eq. 15
        const Eigen::Vector3d c = waterCentroid(i, w, rotation);
        points.emplace_back(m, c);
        p.mass += m;
        moment += m * c;
    }
    if (!(p.mass > 0)) return p;
    p.centerOfMass = moment / p.mass;                    // paper eq. 16
    for (const auto& [m, c] : points) {                  // paper eq. 17, about C_G
        const Eigen::Vector3d d = c - p.centerOfMass;
        p.inertia += m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
    }
    return p;
}

MassProperties WaterGraphSimulation::compose(const MassProperties& body,
                                             const Eigen::Matrix3d& rotation) const {
    const MassProperties water = waterMassProperties(rotation);
    if (!(water.mass > 0)) return body;
    return body + water;  // paper 4.4: parallel-axis theorem (massprops.h operator+)
}

}  // namespace plimsoll
