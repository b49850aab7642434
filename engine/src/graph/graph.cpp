// Water graph: validation and simulation (graph.h; paper section 4, docs/design.md, "Water graph").
// The step below is the evaluation core's (plimsoll_eval/graph.hpp), shared with the runtime.
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
#include "plimsoll/graph/graph.h"

#include "plimsoll/bake/bake.h"

#include "plimsoll_eval/nearest_node.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <unordered_map>

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
        case GraphProblemKind::Empty:
            return "empty-graph";
        case GraphProblemKind::DuplicateId:
            return "duplicate-id";
        case GraphProblemKind::BadCapacity:
            return "bad-capacity";
        case GraphProblemKind::WaterOutOfRange:
            return "water-out-of-range";
        case GraphProblemKind::DanglingPipe:
            return "dangling-pipe";
        case GraphProblemKind::SelfLoop:
            return "self-loop";
        case GraphProblemKind::BadPipe:
            return "bad-pipe";
        case GraphProblemKind::NodeOutsideMesh:
            return "node-outside-mesh";
        case GraphProblemKind::Disconnected:
            return "disconnected";
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
                   (p.error ? "error [" : "warning [") + graphProblemCode(p.kind) +
                   "]: " + p.message;
        }
    }
    return out;
}

namespace {

/// Signed solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee 1983).
double solidAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    return 2.0 * std::atan2(numerator, denominator);
}

/// Inside tests of many points against one closed mesh (validateGraph's nodes-outside check): a
/// sum over every triangle per node made a graph of kMaxGraphNodes against a scanned hull of 1M
/// triangles 1e11 solid angles. A tree of triangle clusters (Barill et al. 2018, "Fast winding
/// numbers", first order): seen from farther than kFar times its radius, a cluster's solid angle
/// is its dipole's, (c - q) . N / |c - q|^3 with c its area-weighted centre and N the sum of its
/// area vectors; nearer, its children's, down to exact sums at the leaves. The estimate is
/// within a few hundredths of the exact number; where it is within 0.25 of the threshold 0.5,
/// the exact sum decides, so the answer is the exact test's.
class InsideTest {
public:
    explicit InsideTest(const TriangleMesh& mesh) : mesh_(mesh) {
        order_.resize(mesh.triangles.size());
        for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<std::uint32_t>(i);
        if (order_.empty()) return;
        cells_.resize(1);
        build(0, 0, static_cast<std::uint32_t>(order_.size()));
    }

    bool inside(const Eigen::Vector3d& q) const {
        const double estimate = winding(q);
        if (std::abs(estimate - 0.5) < 0.25) return windingNumber(mesh_, q) >= 0.5;
        return estimate >= 0.5;
    }

private:
    static constexpr double kFar = 2.5;
    static constexpr std::uint32_t kLeafSize = 8;
    struct Cell {
        Eigen::Vector3d centre =
            Eigen::Vector3d::Zero();  ///< area-weighted, of the triangles below
        Eigen::Vector3d dipole = Eigen::Vector3d::Zero();  ///< sum of their area vectors
        double radius = 0;                                 ///< of every vertex below, about centre
        std::uint32_t begin = 0, end = 0, left = 0;  ///< order_[begin, end); children; 0: leaf
    };

    Eigen::Vector3d corner(std::uint32_t triangle, int k) const {
        return mesh_.positions[mesh_.triangles[triangle][k]];
    }

    void build(std::uint32_t self, std::uint32_t begin, std::uint32_t end) {
        Eigen::Vector3d weighted = Eigen::Vector3d::Zero(), dipole = Eigen::Vector3d::Zero();
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
        Eigen::Vector3d hi = -lo;
        double area = 0;
        for (std::uint32_t k = begin; k < end; ++k) {
            const Eigen::Vector3d a = corner(order_[k], 0), b = corner(order_[k], 1),
                                  c = corner(order_[k], 2);
            const Eigen::Vector3d n = 0.5 * (b - a).cross(c - a);
            const Eigen::Vector3d centroid = (a + b + c) / 3.0;
            weighted += n.norm() * centroid;
            area += n.norm();
            dipole += n;
            lo = lo.cwiseMin(centroid);
            hi = hi.cwiseMax(centroid);
        }
        Cell cell;
        cell.centre =
            area > 0 ? Eigen::Vector3d(weighted / area) : Eigen::Vector3d(0.5 * (lo + hi));
        cell.dipole = dipole;
        for (std::uint32_t k = begin; k < end; ++k)
            for (int j = 0; j < 3; ++j)
                cell.radius = std::max(cell.radius, (corner(order_[k], j) - cell.centre).norm());
        cell.begin = begin;
        cell.end = end;
        cells_[self] = cell;
        if (end - begin <= kLeafSize) return;
        int axis = 0;
        (hi - lo).maxCoeff(&axis);
        const std::uint32_t middle = begin + (end - begin) / 2;
        std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                         [&](std::uint32_t x, std::uint32_t y) {
                             return (corner(x, 0) + corner(x, 1) + corner(x, 2))[axis] <
                                    (corner(y, 0) + corner(y, 1) + corner(y, 2))[axis];
                         });
        const auto left = static_cast<std::uint32_t>(cells_.size());
        cells_.resize(cells_.size() + 2);
        cells_[self].left = left;
        build(left, begin, middle);
        build(left + 1, middle, end);
    }

    double winding(const Eigen::Vector3d& q) const {
        double total = 0;
        std::vector<std::uint32_t> stack{0};
        while (!stack.empty()) {
            const Cell& cell = cells_[stack.back()];
            stack.pop_back();
            const Eigen::Vector3d d = cell.centre - q;
            const double distance = d.norm();
            if (distance > kFar * cell.radius) {
                total += d.dot(cell.dipole) / (distance * distance * distance);
            } else if (cell.left == 0) {
                for (std::uint32_t k = cell.begin; k < cell.end; ++k)
                    total += solidAngle(corner(order_[k], 0) - q, corner(order_[k], 1) - q,
                                        corner(order_[k], 2) - q);
            } else {
                stack.push_back(cell.left);
                stack.push_back(cell.left + 1);
            }
        }
        return total / (4.0 * std::numbers::pi);
    }

    const TriangleMesh& mesh_;
    std::vector<std::uint32_t> order_;
    std::vector<Cell> cells_;
};

}  // namespace

double windingNumber(const TriangleMesh& mesh, const Eigen::Vector3d& point) {
    // Sum of the signed solid angles of the triangles seen from the point, over 4 pi.
    double total = 0;
    for (const Triangle& t : mesh.triangles) {
        total += solidAngle(mesh.positions[t[0]] - point, mesh.positions[t[1]] - point,
                            mesh.positions[t[2]] - point);
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
    // The first node of each id, by hash: a scan per node took minutes at kMaxGraphNodes.
    std::unordered_map<std::string, std::size_t> firstWithId;
    for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
        const GraphNode& n = graph.nodes[i];
        const std::string label = "node " + std::to_string(i) + " '" + n.id + "'";
        if (n.id.empty()) {
            add(GraphProblemKind::DuplicateId, true, "node " + std::to_string(i) + " has no id");
        } else if (const auto [first, added] = firstWithId.emplace(n.id, i); !added) {
            add(GraphProblemKind::DuplicateId, true,
                label + ": id already used by node " + std::to_string(first->second));
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
    auto indexOf = [&](const std::string& id) {
        const auto found = firstWithId.find(id);
        return found == firstWithId.end() ? -1 : static_cast<int>(found->second);
    };
    for (std::size_t i = 0; i < graph.pipes.size(); ++i) {
        const GraphPipe& p = graph.pipes[i];
        const std::string label = "pipe " + std::to_string(i) + " ('" + p.a + "' - '" + p.b + "')";
        const int a = indexOf(p.a), b = indexOf(p.b);
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
        } else if (a >= 0 && b >= 0 && a != b && !(p.length > 0) &&
                   !((graph.nodes[a].position - graph.nodes[b].position).norm() > 0)) {
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
            const int a = indexOf(p.a), b = indexOf(p.b);
            if (a >= 0 && b >= 0 && p.open) parent[root(a)] = root(b);
        }
        std::size_t groups = 0;
        for (std::size_t i = 0; i < parent.size(); ++i)
            groups += root(static_cast<int>(i)) == static_cast<int>(i);
        if (groups > 1) {
            add(GraphProblemKind::Disconnected, false,
                std::to_string(groups) + " groups of nodes that no open pipe joins");
        }
    }
    if (mesh && !mesh->triangles.empty()) {
        const InsideTest insideMesh(*mesh);
        for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
            const GraphNode& n = graph.nodes[i];
            if (!n.position.allFinite()) continue;
            if (!insideMesh.inside(n.position)) {
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
// Simulation: the state and the step are the evaluation core's (plimsoll_eval/graph.hpp, which
// the runtime library compiles too); this class turns the engine's types into its own.

namespace ev = plimsoll_eval;

double WaterGraphSimulation::poiseuilleRate(double dp, double radius, double viscosity,
                                            double length) {
    return ev::GraphFlow::poiseuilleRate(dp, radius, viscosity, length);
}

namespace {

ev::Vec3 toEval(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d fromEval(const ev::Vec3& v) { return {v.x, v.y, v.z}; }

ev::Mat3 toEval(const Eigen::Matrix3d& R) {
    ev::Mat3 m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m.m[i][j] = R(i, j);
    return m;
}

/// The nodes as the shared nearest-node rule sees them.
std::vector<plimsoll_eval::NodeShape> nodeShapes(const WaterGraph& graph) {
    std::vector<plimsoll_eval::NodeShape> shapes;
    shapes.reserve(graph.nodes.size());
    for (const GraphNode& n : graph.nodes)
        shapes.push_back({toEval(n.position), toEval(n.boxSize)});
    return shapes;
}

}  // namespace

int nearestNode(const WaterGraph& graph, const Eigen::Vector3d& point) {
    return plimsoll_eval::nearestNodeByScan(nodeShapes(graph), toEval(point));
}

std::vector<std::int32_t> texelNodeMap(const WaterGraph& graph, const SurfaceTextures& textures) {
    const plimsoll_eval::NearestNodeIndex index(nodeShapes(graph));
    std::vector<std::int32_t> nodes(textures.position.size());
    for (std::size_t i = 0; i < nodes.size(); ++i)
        nodes[i] = index.nearest(toEval(textures.position[i]));
    return nodes;
}

Result<WaterGraphSimulation> WaterGraphSimulation::create(const WaterGraph& graph,
                                                          const SurfaceTextures& textures,
                                                          const std::vector<double>& permeability,
                                                          const GraphSettings& settings) {
    const GraphReport report = validateGraph(graph);
    if (report.hasErrors()) return makeError(ErrorKind::schema, report.format());
    if (!permeability.empty() && permeability.size() != textures.coveredCount()) {
        return makeError(ErrorKind::invalidArgument,
                         "water graph: " + std::to_string(permeability.size()) +
                             " permeability values for " + std::to_string(textures.coveredCount()) +
                             " texel entries");
    }
    if (settings.flow == FlowMode::Poiseuille && !(settings.viscosity > 0)) {
        return makeError(ErrorKind::schema, "water graph: Poiseuille flow needs a viscosity > 0");
    }
    WaterGraphSimulation sim;
    sim.graph_ = graph;
    sim.settings_ = settings;
    std::vector<ev::GraphNodeState> nodes;
    nodes.reserve(graph.nodes.size());
    for (const GraphNode& n : graph.nodes) {
        nodes.push_back({toEval(n.position), n.capacity, n.water, n.sealed, toEval(n.boxSize)});
    }
    // Pipe ends by hash, once: a scan of the nodes per pipe (WaterGraph::indexOf) took minutes
    // at kMaxGraphNodes. The core keeps the indices; the steps never look an id up again.
    std::unordered_map<std::string, std::uint32_t> indexById;
    indexById.reserve(graph.nodes.size());
    for (std::size_t i = 0; i < graph.nodes.size(); ++i)
        indexById.emplace(graph.nodes[i].id, static_cast<std::uint32_t>(i));
    std::vector<ev::GraphPipeState> pipes;
    pipes.reserve(graph.pipes.size());
    for (const GraphPipe& p : graph.pipes)
        pipes.push_back({indexById.at(p.a), indexById.at(p.b), p.radius, p.length, p.open});
    sim.flow_.reset(std::move(nodes), std::move(pipes), settings.seed);
    const plimsoll_eval::NearestNodeIndex nearest(nodeShapes(graph));
    for (std::size_t i = 0; i < permeability.size(); ++i) {
        const double k = std::clamp(permeability[i], 0.0, 1.0);
        if (!(k > 0)) continue;
        ExchangeSample s;
        s.position = textures.position[i];
        s.weight = k * textures.area[i];
        s.node = static_cast<std::uint32_t>(nearest.nearest(toEval(s.position)));
        // A sealed node exchanges nothing: its texels are left out.
        if (!graph.nodes[s.node].sealed) sim.samples_.push_back(s);
    }
    return sim;
}

void WaterGraphSimulation::syncWater() {
    const std::vector<ev::GraphNodeState>& nodes = flow_.nodes();
    for (std::size_t i = 0; i < nodes.size(); ++i) graph_.nodes[i].water = nodes[i].water;
}

double WaterGraphSimulation::storedWater() const { return graph_.totalWater(); }

double WaterGraphSimulation::conservationError() const {
    const GraphTotals& totals = flow_.totals();
    const double in = totals.entered + totals.initial;
    const double balance = in - totals.left - storedWater();
    return std::abs(balance) / std::max(in, 1e-300);
}

void WaterGraphSimulation::setWater(std::size_t node, double water) {
    graph_.nodes.at(node);  // out of range throws, as before the step moved to the core
    flow_.setWater(node, water);
    syncWater();
}

double WaterGraphSimulation::levelOffset(std::size_t node, double water,
                                         const Eigen::Matrix3d& rotation) const {
    return flow_.levelOffset(node, water, toEval(rotation));
}

ExchangeFrame WaterGraphSimulation::exchangeFrame(const Pose& pose, double time) {
    // World height of every node's water surface (a node with no water has none); the levels
    // kept for applyExchange and the flow at the same rotation.
    flow_.prepareLevels(toEval(pose.rotation));
    flow_.nodeSurfaces(pose.translation.y(), toEval(pose.rotation), scratchSurface_);
    ExchangeFrame frame;
    frame.pose = pose;
    frame.time = time;
    frame.nodeSurface = scratchSurface_;
    frame.torricelli = settings_.inflow == InflowModel::Torricelli;
    frame.factor = settings_.exchangeFactor();
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
    const bool moved =
        flow_.applyExchange(pose.translation.y(), toEval(pose.rotation), dt, rates.inflow.data(),
                            rates.outflow.data(), rates.outsideTop.data());
    syncWater();
    return moved;
}

int WaterGraphSimulation::findDischargeNode(int source, const Eigen::Matrix3d& rotation) {
    return flow_.findDischargeNode(source, toEval(rotation));
}

bool WaterGraphSimulation::flowInside(const Eigen::Matrix3d& rotation, double dt) {
    const bool moved = flow_.flowInside(toEval(rotation), dt, settings_);
    syncWater();
    return moved;
}

bool WaterGraphSimulation::step(const Pose& pose, const WaterModel& water, double time, double dt) {
    const bool exchanged = exchange(pose, water, time, dt);
    const bool flowed = flowInside(pose.rotation, dt);
    return exchanged || flowed;
}

MassProperties WaterGraphSimulation::waterMassProperties(const Eigen::Matrix3d& rotation) const {
    const ev::WaterMass w = flow_.waterMass(toEval(rotation), settings_);
    MassProperties p;
    if (!(w.mass > 0)) return p;
    p.mass = w.mass;  // the water's volume is not the body's: left out, as before
    p.centerOfMass = fromEval(w.centerOfMass);
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) p.inertia(r, k) = w.inertia[r][k];
    return p;
}

MassProperties WaterGraphSimulation::compose(const MassProperties& body,
                                             const Eigen::Matrix3d& rotation) const {
    const MassProperties water = waterMassProperties(rotation);
    if (!(water.mass > 0)) return body;
    return body + water;  // paper 4.4: parallel-axis theorem (massprops.h operator+)
}

}  // namespace plimsoll
