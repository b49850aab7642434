// The water graph's simulation: the evaluation core's step (plimsoll_eval/graph.hpp), the one
// the engine's WaterGraphSimulation compiles, over the bundle's graph and permeable samples.
// The layout (nodes, pipes, exchange points) is the bundle's and shared; each WaterGraph holds
// only the state its steps change. tests/runtime/test_runtime_conformance.cpp steps the engine
// and the runtime side by side.
#include "plimsoll_runtime/runtime.hpp"

#include "bytes.hpp"
#include "vec.hpp"

#include "plimsoll_eval/graph.hpp"

#include <cmath>

namespace plimsoll_runtime {

namespace ev = plimsoll_eval;

/// The layout in the step's form: the permeable samples as exchange points and the graph at
/// its exported water, which every WaterGraph of the bundle starts from.
struct GraphLayout::Prepared {
    std::vector<ev::ExchangePoint> points;
    ev::GraphFlow start;
};

struct WaterGraph::Step {
    ev::GraphFlow flow;
};

namespace {

ev::Mat3 rotation(const Quat& q) { return ev::rotationMatrix({q.w, q.x, q.y, q.z}); }

}  // namespace

GraphLayout::GraphLayout() = default;
GraphLayout::~GraphLayout() = default;

void GraphLayout::prepare(std::vector<Exchange> exchange) {
    auto prepared = std::make_unique<Prepared>();
    std::vector<ev::GraphNodeState> nodes;
    nodes.reserve(nodes_.size());
    for (const GraphNode& n : nodes_) {
        nodes.push_back({toEval(n.position), n.capacity, n.water, n.sealed, toEval(n.box)});
    }
    std::vector<ev::GraphPipeState> pipes;
    pipes.reserve(pipes_.size());
    for (const GraphPipe& p : pipes_) {
        pipes.push_back({static_cast<std::uint32_t>(p.nodeA), static_cast<std::uint32_t>(p.nodeB),
                         p.radius, p.length, p.open});
    }
    prepared->start.reset(std::move(nodes), std::move(pipes), settings_.seed);
    prepared->points.reserve(exchange.size());
    for (const Exchange& s : exchange)
        prepared->points.push_back({toEval(s.position), s.weight, s.node});
    prepared_ = std::move(prepared);
}

std::size_t GraphLayout::permeableSamples() const {
    return prepared_ ? prepared_->points.size() : 0;
}

std::uint64_t GraphLayout::memoryBytes() const {
    std::uint64_t bytes = sizeof(GraphLayout) + pipes_.capacity() * sizeof(GraphPipe) +
                          sampleNodes_.capacity() * sizeof(int);
    for (const GraphNode& n : nodes_)
        bytes += sizeof(GraphNode) + n.id.capacity() + n.name.capacity();
    if (prepared_) {
        bytes += sizeof(Prepared) + prepared_->points.capacity() * sizeof(ev::ExchangePoint) +
                 prepared_->start.memoryBytes();
    }
    return bytes;
}

WaterGraph::WaterGraph(const GraphLayout& layout)
    : layout_(&layout), settings_(layout.settings()), step_(std::make_unique<Step>()) {
    step_->flow = layout.prepared_->start;
}

WaterGraph::WaterGraph(const WaterGraph& other)
    : layout_(other.layout_),
      settings_(other.settings_),
      step_(std::make_unique<Step>(*other.step_)) {}

WaterGraph::~WaterGraph() = default;

std::uint64_t WaterGraph::memoryBytes() const {
    return sizeof(WaterGraph) + sizeof(Step) + step_->flow.memoryBytes();
}

double WaterGraph::water(std::size_t node) const {
    return node < nodeCount() ? step_->flow.nodes()[node].water : 0.0;
}

void WaterGraph::setMedium(double density, double viscosity, double gravity) {
    settings_.density = density;
    settings_.viscosity = viscosity;
    settings_.gravity = gravity;
}

void WaterGraph::saveState(std::vector<std::uint8_t>& out) const {
    // GraphFlow::state()'s fields, written straight from the flow (no copy of the water).
    const ev::GraphFlow& flow = step_->flow;
    putBytes(out, static_cast<std::uint64_t>(flow.nodes().size()));
    for (const ev::GraphNodeState& n : flow.nodes()) putBytes(out, n.water);
    putBytes(out, flow.randomState());
    putBytes(out, flow.totals().entered);
    putBytes(out, flow.totals().left);
    putBytes(out, flow.totals().initial);
    putBytes(out, flow.totals().moved);
}

bool WaterGraph::restoreState(const std::vector<std::uint8_t>& in, std::size_t& at) {
    std::size_t cursor = at;
    std::uint64_t count = 0;
    if (!takeBytes(in, cursor, count) || count != nodeCount()) return false;
    ev::GraphFlow::State s;
    s.water.resize(nodeCount());
    for (std::size_t i = 0; i < s.water.size(); ++i) {
        double& w = s.water[i];
        if (!takeBytes(in, cursor, w) || !(w >= 0) || !(w <= layout_->nodes()[i].capacity))
            return false;
    }
    if (!takeBytes(in, cursor, s.random) || !takeBytes(in, cursor, s.totals.entered) ||
        !takeBytes(in, cursor, s.totals.left) || !takeBytes(in, cursor, s.totals.initial) ||
        !takeBytes(in, cursor, s.totals.moved))
        return false;
    if (!step_->flow.restore(s)) return false;
    at = cursor;
    return true;
}

double WaterGraph::storedWater() const { return step_->flow.storedWater(); }
double WaterGraph::entered() const { return step_->flow.totals().entered; }
double WaterGraph::left() const { return step_->flow.totals().left; }

void WaterGraph::setWater(std::size_t node, double water) {
    if (node < nodeCount()) step_->flow.setWater(node, water);
}

double WaterGraph::levelOffset(std::size_t node, double water, const Quat& orientation) const {
    return step_->flow.levelOffset(node, water, rotation(orientation));
}

namespace {

/// One exchange pass's rates for the flow at (pose, R) with the node surfaces `nodeSurface`:
/// the outside surface from the water's heights on the exchange's lattice, the nodes the
/// permeable points touch asked in one call (a game's water answers a batch far faster than
/// one point at a time); on flat water only the points' heights.
void exchangeRates(const std::vector<ev::ExchangePoint>& points, const Pose& pose,
                   const ev::Mat3& R, const Water& water, double time, std::size_t nodes,
                   const double* nodeSurface, const GraphSettings& s, ev::ExchangeRates& rates) {
    // Per thread: sized on a thread's first call, reused after.
    thread_local std::vector<ev::Vec3> world;
    thread_local std::vector<double> ys, surface;
    thread_local ev::ExchangeLattice lattice;
    const std::size_t n = points.size();
    if (!water.heights && !water.height) {
        ev::exchangeHeights(points, R, pose.position.y, ys);
        const double level = water.level;
        ev::exchangePass(
            points, ys.data(), [level](std::size_t) { return level; }, nodes, nodeSurface,
            s.inflow == InflowModel::Torricelli, s.exchangeFactor(), rates);
        return;
    }
    ev::exchangePositions(points, R, toEval(pose.position), world);
    ys.resize(n);
    for (std::size_t i = 0; i < n; ++i) ys[i] = world[i].y;
    ev::exchangeSurfaces(
        world, ev::kExchangeLatticeSpacing,
        [&](std::size_t count, const double* x, const double* z, double* out) {
            if (count == 0) return;
            if (water.heights) {
                water.heights(count, x, z, time, out);
            } else {
                for (std::size_t i = 0; i < count; ++i) out[i] = water.heightAt(x[i], z[i], time);
            }
        },
        lattice, surface);
    const double* f = surface.data();
    ev::exchangePass(
        points, ys.data(), [f](std::size_t i) { return f[i]; }, nodes, nodeSurface,
        s.inflow == InflowModel::Torricelli, s.exchangeFactor(), rates);
}

}  // namespace

NodeInflow WaterGraph::inflow(const Pose& pose, const Water& water, double time) const {
    const ev::Mat3 R = rotation(pose.orientation);
    std::vector<double> nodeSurface;
    step_->flow.nodeSurfaces(pose.position.y, R, nodeSurface);
    ev::ExchangeRates rates;
    exchangeRates(layout_->prepared_->points, pose, R, water, time, nodeCount(), nodeSurface.data(),
                  settings_, rates);
    NodeInflow out;
    out.inflow = std::move(rates.inflow);
    out.outflow = std::move(rates.outflow);
    out.outsideTop = std::move(rates.outsideTop);
    return out;
}

bool WaterGraph::exchange(const Pose& pose, const Water& water, double time, double dt) {
    if (layout_->prepared_->points.empty()) return false;
    const ev::Mat3 R = rotation(pose.orientation);
    ev::GraphFlow& flow = step_->flow;
    // The levels once at R: the node surfaces here, applyExchange and the flow after read them.
    flow.prepareLevels(R);
    thread_local std::vector<double> nodeSurface;
    thread_local ev::ExchangeRates rates;
    flow.nodeSurfaces(pose.position.y, R, nodeSurface);
    exchangeRates(layout_->prepared_->points, pose, R, water, time, nodeCount(), nodeSurface.data(),
                  settings_, rates);
    return flow.applyExchange(pose.position.y, R, dt, rates.inflow.data(), rates.outflow.data(),
                              rates.outsideTop.data());
}

bool WaterGraph::flowInside(const Quat& orientation, double dt) {
    return step_->flow.flowInside(rotation(orientation), dt, settings_);
}

bool WaterGraph::step(const Pose& pose, const Water& water, double time, double dt) {
    const bool exchanged = exchange(pose, water, time, dt);
    const bool flowed = flowInside(pose.orientation, dt);
    return exchanged || flowed;
}

MassProperties WaterGraph::waterMass(const Quat& orientation) const {
    const ev::WaterMass w = step_->flow.waterMass(rotation(orientation), settings_);
    MassProperties p;
    p.mass = w.mass;
    p.volume = w.volume;
    p.centerOfMass = fromEval(w.centerOfMass);
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) p.inertia[r][k] = w.inertia[r][k];
    return p;
}

}  // namespace plimsoll_runtime
