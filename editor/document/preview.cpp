// The live preview session (preview.h).
#include "document/preview.h"

#include "plimsoll/body_setup.h"
#include "plimsoll/file_util.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>

namespace plimsoll::editor {

namespace {
constexpr double kDegrees = 180.0 / std::numbers::pi;
/// The grab spring's default natural frequency: firm enough to drag a body through the water,
/// slow enough for a 60 Hz frame with a few sub-steps.
constexpr double kGrabFrequencyHz = 1.5;
}  // namespace

Wrench springWrench(const SimulatedBody& body, const RigidBodyState& state,
                    const Eigen::Vector3d& objectPoint, const Eigen::Vector3d& target,
                    double stiffness, double damping) {
    const Pose pose = poseOf(state, body.mass);
    const Eigen::Vector3d point = pose.apply(objectPoint);
    const Eigen::Vector3d arm = point - state.position;
    const Eigen::Vector3d velocity =
        linearVelocity(state, body.mass) + angularVelocity(state, body.mass).cross(arm);
    Wrench w;
    w.force = stiffness * (target - point) - damping * velocity;
    w.torque = arm.cross(w.force);
    return w;
}

Eigen::Vector2d heelAndTrimDegrees(const Eigen::Matrix3d& rotation) {
    const Eigen::Vector3d side = rotation.col(2), bow = rotation.col(0);
    return {-std::asin(std::clamp(side.y(), -1.0, 1.0)) * kDegrees,
            std::asin(std::clamp(bow.y(), -1.0, 1.0)) * kDegrees};
}

Eigen::Vector3d eulerDegrees(const Eigen::Matrix3d& rotation) {
    // R = Rz(c) Ry(b) Rx(a): eulerAngles(2, 1, 0) returns (c, b, a).
    const Eigen::Vector3d zyx = rotation.eulerAngles(2, 1, 0);
    return Eigen::Vector3d(zyx.z(), zyx.y(), zyx.x()) * kDegrees;
}

const PlotSeries* PreviewHistory::find(const std::string& name) const {
    for (const PlotSeries& s : series) {
        if (s.name == name) return &s;
    }
    return nullptr;
}

Status writeHistoryCsv(const PreviewHistory& history, const std::vector<std::string>& names,
                       const std::filesystem::path& path) {
    std::vector<const PlotSeries*> columns;
    if (names.empty()) {
        for (const PlotSeries& s : history.series) columns.push_back(&s);
    }
    for (const std::string& name : names) {
        const PlotSeries* s = history.find(name);
        if (!s) return makeError(path.string() + ": no plotted quantity named '" + name + "'");
        columns.push_back(s);
    }
    auto quoted = [](const std::string& text) {
        std::string out = "\"";
        for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
        return out + "\"";
    };
    return writeFileAtomically(path, [&](std::ostream& out) {
        out << "time (s)";
        for (const PlotSeries* s : columns) out << ',' << quoted(s->name + " (" + s->unit + ")");
        out << '\n' << std::setprecision(17);
        for (std::size_t row = 0; row < history.time.size(); ++row) {
            out << history.time[row];
            for (const PlotSeries* s : columns) out << ',' << s->values[row];
            out << '\n';
        }
        return static_cast<bool>(out);
    });
}

PreviewSession::~PreviewSession() {
    // A rebuild still baking finishes before the session goes (its world holds the backend).
    if (pending_.valid()) pending_.wait();
}

namespace {

/// Passes every call to the real backend and sums the kernel time of each evaluation: World
/// evaluates once per sub-step (four times per RK4 step), and the backend keeps only the last.
class KernelTimer final : public BuoyancyBackend {
public:
    KernelTimer(std::unique_ptr<BuoyancyBackend> inner, std::shared_ptr<double> total)
        : inner_(std::move(inner)), total_(std::move(total)) {}
    std::string deviceName() const override { return inner_->deviceName(); }
    std::size_t addBody(const SurfaceTextures& textures, const Eigen::Vector3d& centre) override {
        return inner_->addBody(textures, centre);
    }
    Status updateBody(std::size_t id, const SurfaceTextures& textures,
                      const Eigen::Vector3d& centre) override {
        return inner_->updateBody(id, textures, centre);
    }
    Status evaluate(std::span<const BodyRequest> requests, const WaterModel& water,
                    std::span<BuoyancyResult> results) override {
        Status s = inner_->evaluate(requests, water, results);
        *total_ += inner_->lastTimings().kernelMs;
        return s;
    }
    FrameTimings lastTimings() const override { return inner_->lastTimings(); }
    std::size_t addExchangeSet(std::span<const ExchangeSample> samples, std::size_t nodes) override {
        return inner_->addExchangeSet(samples, nodes);
    }
    Status evaluateExchange(std::size_t set, const ExchangeFrame& frame, const WaterModel& water,
                            ExchangeSums& sums) override {
        Status s = inner_->evaluateExchange(set, frame, water, sums);
        *total_ += inner_->lastTimings().kernelMs;
        return s;
    }

private:
    std::unique_ptr<BuoyancyBackend> inner_;
    std::shared_ptr<double> total_;
};

}  // namespace

Result<PreviewSession::Built> PreviewSession::build(const Project& project,
                                                    const std::string& device) {
    Result<std::unique_ptr<BuoyancyBackend>> backend = createBuoyancyBackend(device);
    if (!backend) return backend.error();
    auto total = std::make_shared<double>(0.0);
    Result<std::unique_ptr<World>> world =
        World::create(project, std::make_unique<KernelTimer>(std::move(*backend), total));
    if (!world) return world.error();
    return Built{std::move(*world), std::move(total)};
}

Result<std::unique_ptr<PreviewSession>> PreviewSession::create(const Project& project,
                                                               const std::string& device) {
    if (project.bodies.empty()) return makeError("the live preview needs at least one body");
    std::unique_ptr<PreviewSession> session(new PreviewSession());
    session->project_ = project;
    session->device_ = device;
    Result<Built> built = build(project, device);
    if (!built) return built.error();
    session->world_ = std::move(built->world);
    session->kernelTotalMs_ = std::move(built->kernelTotalMs);
    session->record();
    return session;
}

int PreviewSession::textureSize() const { return project_.bodies.front().textureSize; }

std::size_t PreviewSession::coveredTexels() const {
    std::size_t n = 0;
    for (const SimulatedBody& b : world_->bodies()) n += b.textures.coveredCount();
    return n;
}

void PreviewSession::setTimeScale(double scale) {
    timeScale_ = std::clamp(std::isfinite(scale) ? scale : 1.0, 0.01, 10.0);
}

void PreviewSession::setWater(const WaterModel& water) {
    project_.water = water;
    world_->setWater(water);
}

void PreviewSession::setIntegrator(Integrator integrator) {
    project_.simulation.integrator = integrator;
    world_->setIntegrator(integrator);
}

void PreviewSession::requestTextureSize(int size) {
    for (BodyDesc& body : project_.bodies) body.textureSize = size;
    // A pending rebuild for another size is left to finish and dropped (std::future's
    // destructor of an async result would block here: keep it until it is ready).
    if (pending_.valid()) pending_.wait();
    pending_ = std::async(std::launch::async, [project = project_, device = device_] {
        Rebuilt out;
        Result<Built> built = build(project, device);
        if (built) out.built = std::move(*built);
        else out.error = built.error().message;
        return out;
    });
}

Status PreviewSession::swapIn(Built built) {
    std::unique_ptr<World> next = std::move(built.world);
    // The new bake's centre of mass differs a little from the old one's: carry the place,
    // orientation and momenta, which keeps the motion going.
    for (std::size_t i = 0; i < next->bodies().size() && i < world_->bodies().size(); ++i) {
        if (Status s = next->setBodyState(i, world_->bodies()[i].state); !s.ok()) return s;
    }
    next->setTime(world_->time());
    world_ = std::move(next);
    kernelTotalMs_ = std::move(built.kernelTotalMs);
    checkBackend_.reset();
    checkIds_.clear();
    checkMeshes_.clear();
    if (grabbedBody_) installGrab();
    return Ok{};
}

Status PreviewSession::finishRebuild() {
    if (!pending_.valid()) return Ok{};
    Rebuilt next = pending_.get();
    if (!next.built.world) return makeError(next.error);
    return swapIn(std::move(next.built));
}

Status PreviewSession::advance() {
    if (pending_.valid() &&
        pending_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
        if (Status s = finishRebuild(); !s.ok()) return s;
    }
    const std::size_t stepsBefore = world_->statistics().steps;
    const double kernelBefore = kernelTotalMs_ ? *kernelTotalMs_ : 0.0;
    const auto start = std::chrono::steady_clock::now();
    grabForceSum_ = Eigen::Vector3d::Zero();
    if (Status s = world_->advanceFrame(); !s.ok()) return s;
    timings_.frameMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    // Every evaluation of the frame (one per sub-step, four per RK4 step), summed by World.
    timings_.kernelMs = (kernelTotalMs_ ? *kernelTotalMs_ : 0.0) - kernelBefore;
    timings_.subSteps = static_cast<int>(world_->statistics().steps - stepsBefore);
    // The spring's impulse: each sub-step applied the force it returned for dt.
    const std::size_t steps = world_->statistics().steps - stepsBefore;
    if (grabbedBody_ && steps > 0 && project_.simulation.integrator != Integrator::RK4) {
        grabImpulse_ += grabForceSum_ * (project_.simulation.timeStep / static_cast<double>(steps));
    }
    record();
    return Ok{};
}

Status PreviewSession::step() { return advance(); }

Result<int> PreviewSession::update(double wallSeconds) {
    if (!playing_) {
        timings_.framesLastUpdate = 0;
        return 0;
    }
    const double frame = project_.simulation.timeStep;
    accumulator_ += std::max(0.0, wallSeconds) * timeScale_;
    // A frame owed to within rounding (2.5 + 0.5 frames of wall time) is a frame owed.
    const double due = frame * (1.0 - 1e-9);
    int frames = 0;
    const auto start = std::chrono::steady_clock::now();
    while (accumulator_ >= due && frames < kMaxCatchUpFrames) {
        if (Status s = advance(); !s.ok()) return s.error();
        accumulator_ = std::max(0.0, accumulator_ - frame);
        ++frames;
        // A slow device: one frame per update at least, then no more than the UI can spare.
        if (std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count() > kUpdateBudgetMs)
            break;
    }
    if (accumulator_ >= due) {
        // Behind by more than the cap: drop the rest rather than owe it forever.
        timings_.droppedFrames += static_cast<int>(accumulator_ / frame);
        accumulator_ = std::fmod(accumulator_, frame);
    }
    timings_.framesLastUpdate = frames;
    return frames;
}

Status PreviewSession::reset() {
    // A fresh world from the project as it stands (with the settings changed while running):
    // the starting states, time 0 and full water graphs as the file says.
    if (pending_.valid()) pending_.wait();
    pending_ = {};
    Result<Built> built = build(project_, device_);
    if (!built) return built.error();
    world_ = std::move(built->world);
    kernelTotalMs_ = std::move(built->kernelTotalMs);
    checkBackend_.reset();
    checkIds_.clear();
    checkMeshes_.clear();
    accumulator_ = 0;
    grabbedBody_.reset();
    grabImpulse_ = Eigen::Vector3d::Zero();
    history_.time.clear();
    history_.series.clear();
    timings_ = {};
    record();
    return Ok{};
}

Status PreviewSession::grab(std::size_t body, const Eigen::Vector3d& objectPoint,
                            const Eigen::Vector3d& target, double stiffness) {
    if (body >= world_->bodies().size()) return makeError("grab: no body " + std::to_string(body));
    const double mass = world_->bodies()[body].mass.mass;
    const double omega = 2.0 * std::numbers::pi * kGrabFrequencyHz;
    grabStiffness_ = stiffness > 0 ? stiffness : mass * omega * omega;
    grabDamping_ = 2.0 * std::sqrt(grabStiffness_ * mass);  // critical for the body's mass
    grabbedBody_ = body;
    grabObjectPoint_ = objectPoint;
    grabTarget_ = target;
    grabImpulse_ = Eigen::Vector3d::Zero();
    installGrab();
    return Ok{};
}

void PreviewSession::installGrab() {
    const std::size_t body = *grabbedBody_;
    (void)world_->setExternalForce(body, [this](const SimulatedBody& b, const RigidBodyState& s) {
        const Wrench w = springWrench(b, s, grabObjectPoint_, grabTarget_, grabStiffness_,
                                      grabDamping_);
        grabForceSum_ += w.force;
        return w;
    });
}

void PreviewSession::release() {
    if (grabbedBody_) (void)world_->setExternalForce(*grabbedBody_, {});
    grabbedBody_.reset();
}

Eigen::Vector3d PreviewSession::grabPoint() const {
    if (!grabbedBody_) return Eigen::Vector3d::Zero();
    return world_->bodies()[*grabbedBody_].pose().apply(grabObjectPoint_);
}

Result<SubmergedVolumeCheck> PreviewSession::volumeCheck(std::size_t i) {
    if (i >= world_->bodies().size()) return makeError("volume check: no body " + std::to_string(i));
    if (!checkBackend_) {
        Result<std::unique_ptr<BuoyancyBackend>> backend = createBuoyancyBackend(device_);
        if (!backend) return backend.error();
        checkBackend_ = std::move(*backend);
        checkIds_.assign(world_->bodies().size(), SIZE_MAX);
        checkMeshes_.assign(world_->bodies().size(), TriangleMesh{});
    }
    const SimulatedBody& body = world_->bodies()[i];
    if (checkIds_[i] == SIZE_MAX) {
        // The mesh the world baked (its atlas applied: the same geometry as the file).
        Result<PreparedBodyMesh> prepared = prepareBodyMesh(project_, i);
        if (!prepared) return prepared.error();
        checkMeshes_[i] = std::move(prepared->mesh);
        checkIds_[i] = checkBackend_->addBody(body.textures, body.backendCenter);
    }
    BodyFrame frame;
    frame.pose = body.pose();
    frame.centerOfMass = body.backendCenter;
    frame.time = world_->time();
    return checkSubmergedVolume(*checkBackend_, checkIds_[i], checkMeshes_[i], frame,
                                project_.water.level, body.fluid);
}

void PreviewSession::record() {
    const std::vector<SimulatedBody>& bodies = world_->bodies();
    std::vector<std::pair<std::string, std::pair<std::string, double>>> row;
    const Eigen::Vector3d gravity = project_.simulation.gravity;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const SimulatedBody& b = bodies[i];
        const std::string name = b.name.empty() ? "body " + std::to_string(i) : b.name;
        const Eigen::Vector2d ht = heelAndTrimDegrees(b.state.orientation.toRotationMatrix());
        const bool flat = project_.water.kind == WaterModel::Kind::Flat;
        const Eigen::Vector3d buoyancy = flat ? b.buoyancy.force : b.buoyancy.pressureForce;
        row.push_back({name + " submerged volume", {"m^3", b.buoyancy.submergedVolume}});
        row.push_back({name + " heel", {"deg", ht.x()}});
        row.push_back({name + " trim", {"deg", ht.y()}});
        row.push_back({name + " height", {"m", b.state.position.y()}});
        row.push_back({name + " weight", {"N", (b.mass.mass * gravity).y()}});
        row.push_back({name + " buoyancy", {"N", buoyancy.y()}});
        row.push_back({name + " drag", {"N", b.buoyancy.dragForce.norm()}});
        if (const WaterGraphSimulation* graph = world_->waterGraph(i)) {
            for (const GraphNode& node : graph->graph().nodes) {
                row.push_back({name + " water " + (node.name.empty() ? node.id : node.name),
                               {"m^3", node.water}});
            }
        }
    }
    // A new layout (first row, or bodies / nodes changed): start the history over.
    bool same = history_.series.size() == row.size();
    for (std::size_t k = 0; same && k < row.size(); ++k) same = history_.series[k].name == row[k].first;
    if (!same) {
        history_.time.clear();
        history_.series.clear();
        for (const auto& [name, value] : row) history_.series.push_back({name, value.first, {}});
    }
    if (history_.time.size() >= history_.capacity) {
        const std::size_t drop = history_.capacity / 10 + 1;  // amortised: not one per frame
        history_.time.erase(history_.time.begin(), history_.time.begin() + drop);
        for (PlotSeries& s : history_.series) s.values.erase(s.values.begin(), s.values.begin() + drop);
    }
    history_.time.push_back(world_->time());
    for (std::size_t k = 0; k < row.size(); ++k) history_.series[k].values.push_back(row[k].second.second);
}

}  // namespace plimsoll::editor
