// The water graph's simulation: the evaluation core's step (plimsoll_eval/graph.hpp), the one
// the engine's WaterGraphSimulation compiles, over the bundle's graph and permeable samples.
// tests/runtime/test_runtime_conformance.cpp steps both side by side.
#include "plimsoll_runtime/runtime.hpp"

#include "vec.hpp"

#include "plimsoll_eval/graph.hpp"

#include <cmath>
#include <cstring>

namespace plimsoll_runtime {

namespace ev = plimsoll_eval;

struct WaterGraph::Step {
    ev::GraphFlow flow;
    std::vector<ev::ExchangePoint> points;
};

namespace {

ev::Mat3 rotation(const Quat& q) { return ev::rotationMatrix({q.w, q.x, q.y, q.z}); }

ev::GraphFlowSettings flowSettings(const GraphSettings& s) {
    ev::GraphFlowSettings f;
    f.torricelli = s.torricelli;
    f.inflowRate = s.inflowRate;
    f.dischargeCoefficient = s.dischargeCoefficient;
    f.diffusion = s.diffusion;
    f.diffusionPressure = s.diffusionPressure;
    f.freeSurface = s.freeSurface;
    f.density = s.density;
    f.viscosity = s.viscosity;
    f.gravity = s.gravity;
    return f;
}

}  // namespace

WaterGraph::WaterGraph() : step_(std::make_unique<Step>()) {}
WaterGraph::~WaterGraph() = default;

void WaterGraph::prepare() {
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
    step_->flow.reset(std::move(nodes), std::move(pipes), settings_.seed);
    step_->points.clear();
    step_->points.reserve(exchange_.size());
    for (const Exchange& s : exchange_) step_->points.push_back({toEval(s.position), s.weight, s.node});
}

void WaterGraph::syncWater() {
    const std::vector<ev::GraphNodeState>& nodes = step_->flow.nodes();
    for (std::size_t i = 0; i < nodes.size(); ++i) nodes_[i].water = nodes[i].water;
}

std::uint64_t WaterGraph::stepBytes() const {
    return sizeof(Step) + step_->flow.memoryBytes() +
           step_->points.capacity() * sizeof(ev::ExchangePoint);
}

namespace {
template <class T>
void put(std::vector<std::uint8_t>& out, const T& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    out.insert(out.end(), p, p + sizeof(T));
}
template <class T>
bool take(const std::vector<std::uint8_t>& in, std::size_t& at, T& v) {
    if (in.size() < at || in.size() - at < sizeof(T)) return false;
    std::memcpy(&v, in.data() + at, sizeof(T));
    at += sizeof(T);
    return true;
}
}  // namespace

void WaterGraph::saveState(std::vector<std::uint8_t>& out) const {
    const ev::GraphFlow::State s = step_->flow.state();
    put(out, static_cast<std::uint64_t>(s.water.size()));
    for (double w : s.water) put(out, w);
    put(out, s.random);
    put(out, s.totals.entered);
    put(out, s.totals.left);
    put(out, s.totals.initial);
    put(out, s.totals.moved);
}

bool WaterGraph::restoreState(const std::vector<std::uint8_t>& in, std::size_t& at) {
    std::size_t cursor = at;
    std::uint64_t count = 0;
    if (!take(in, cursor, count) || count != nodes_.size()) return false;
    ev::GraphFlow::State s;
    s.water.resize(nodes_.size());
    for (double& w : s.water) {
        if (!take(in, cursor, w) || !(w >= 0) || !std::isfinite(w)) return false;
    }
    if (!take(in, cursor, s.random) || !take(in, cursor, s.totals.entered) || !take(in, cursor, s.totals.left) ||
        !take(in, cursor, s.totals.initial) || !take(in, cursor, s.totals.moved))
        return false;
    if (!step_->flow.restore(s)) return false;
    syncWater();
    at = cursor;
    return true;
}

double WaterGraph::storedWater() const { return step_->flow.storedWater(); }
double WaterGraph::entered() const { return step_->flow.totals().entered; }
double WaterGraph::left() const { return step_->flow.totals().left; }

void WaterGraph::setWater(std::size_t node, double water) {
    if (node >= nodes_.size()) return;
    step_->flow.setWater(node, water);
    syncWater();
}

double WaterGraph::levelOffset(std::size_t node, double water, const Quat& orientation) const {
    return step_->flow.levelOffset(node, water, rotation(orientation));
}

NodeInflow WaterGraph::inflow(const Pose& pose, const Water& water, double time) const {
    const ev::Mat3 R = rotation(pose.orientation);
    std::vector<double> surface;
    step_->flow.nodeSurfaces(pose.position.y, R, surface);
    const ev::GraphFlowSettings s = flowSettings(settings_);
    ev::ExchangeRates rates;
    ev::exchangePass(
        step_->points, nodes_.size(), R, toEval(pose.position), time, surface.data(),
        s.torricelli, s.exchangeFactor(),
        [&water](double x, double z, double t) { return water.heightAt(x, z, t); }, rates);
    NodeInflow out;
    out.inflow = std::move(rates.inflow);
    out.outflow = std::move(rates.outflow);
    out.outsideTop = std::move(rates.outsideTop);
    return out;
}

bool WaterGraph::exchange(const Pose& pose, const Water& water, double time, double dt) {
    if (exchange_.empty()) return false;
    const NodeInflow rates = inflow(pose, water, time);
    const bool moved = step_->flow.applyExchange(pose.position.y, rotation(pose.orientation), dt,
                                                 rates.inflow.data(), rates.outflow.data(),
                                                 rates.outsideTop.data());
    syncWater();
    return moved;
}

bool WaterGraph::flowInside(const Quat& orientation, double dt) {
    const bool moved = step_->flow.flowInside(rotation(orientation), dt, flowSettings(settings_));
    syncWater();
    return moved;
}

bool WaterGraph::step(const Pose& pose, const Water& water, double time, double dt) {
    const bool exchanged = exchange(pose, water, time, dt);
    const bool flowed = flowInside(pose.orientation, dt);
    return exchanged || flowed;
}

MassProperties WaterGraph::waterMass(const Quat& orientation) const {
    const ev::WaterMass w = step_->flow.waterMass(rotation(orientation), flowSettings(settings_));
    MassProperties p;
    p.mass = w.mass;
    p.volume = w.volume;
    p.centerOfMass = fromEval(w.centerOfMass);
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) p.inertia[r][k] = w.inertia[r][k];
    return p;
}

}  // namespace plimsoll_runtime
