// The live preview session (preview.h).
#include "document/preview.h"

#include "document/document.h"
#include "document/physics_bakes.h"  // lowerThisThreadsPriority

#include "plimsoll/graph/graph.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/scene/controlled_bake.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <thread>

namespace plimsoll::editor {

namespace {
constexpr double kDegrees = 180.0 / std::numbers::pi;
/// The grab spring's default natural frequency: firm enough to drag a body through the water,
/// slow enough for a 60 Hz frame with a few sub-steps.
constexpr double kGrabFrequencyHz = 1.5;
/// The sea floor's contact frequency (floorContactWrench): stiff enough that a resting body
/// sinks into it at most 1.6 cm, slow enough for a 60 Hz frame of a few sub-steps.
constexpr double kFloorFrequencyHz = 4.0;
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

Wrench floorContactWrench(const SimulatedBody& body, const RigidBodyState& state,
                          const std::vector<Eigen::Vector3d>& objectPoints, double floorY,
                          double friction) {
    Wrench w;
    const Pose pose = poseOf(state, body.mass);
    double deepest = 0, depthSum = 0;
    for (const Eigen::Vector3d& q : objectPoints) {
        const double depth = floorY - (pose.rotation.row(1).dot(q) + pose.translation.y());
        if (depth > 0) {
            deepest = std::max(deepest, depth);
            depthSum += depth;
        }
    }
    if (depthSum <= 0) return w;
    const double omega = 2 * std::numbers::pi * kFloorFrequencyHz;
    const double stiffness = body.mass.mass * omega * omega, damping = 2 * body.mass.mass * omega;
    const Eigen::Vector3d v = linearVelocity(state, body.mass);
    const Eigen::Vector3d spin = angularVelocity(state, body.mass);
    for (const Eigen::Vector3d& q : objectPoints) {
        const Eigen::Vector3d p = pose.apply(q);
        const double depth = floorY - p.y();
        if (depth <= 0) continue;
        const double share = depth / depthSum;
        const Eigen::Vector3d arm = p - state.position;
        const Eigen::Vector3d velocity = v + spin.cross(arm);
        const double push = std::max(0.0, share * (stiffness * deepest - damping * velocity.y()));
        Eigen::Vector3d force(0, push, 0);
        const Eigen::Vector3d sliding(velocity.x(), 0, velocity.z());
        const double speed = sliding.norm();
        if (speed > 0) force -= sliding * std::min(share * damping, friction * push / speed);
        w.force += force;
        w.torque += arm.cross(force);
    }
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
        if (!s)
            return makeError(ErrorKind::invalidArgument,
                             path.string() + ": no plotted quantity named '" + name + "'");
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

/// One rebake at a new texture size on its own thread. The thread writes `scene`, `built` and
/// `error` and then sets `done`; the session reads them only after seeing `done`.
struct PreviewSession::RebuildJob {
    int size = 0;
    std::atomic<bool> cancel{false};
    std::atomic<double> progress{0.0};
    std::atomic<bool> done{false};
    Scene scene;  ///< rebaked at `size`
    Built built;
    std::optional<Error> error;
    std::thread thread;
};

PreviewSession::~PreviewSession() {
    // Rebuilds still baking stop and finish before the session goes (their worlds hold
    // backends of the same device).
    if (pending_) abandoned_.push_back(std::move(pending_));
    for (auto& job : abandoned_) job->cancel = true;
    for (auto& job : abandoned_) job->thread.join();
}

namespace {

/// Passes every call to the real backend and sums the kernel time of each evaluation: World
/// evaluates once per sub-step (four times per RK4 step), and the backend keeps only the last.
class KernelTimer final : public BuoyancyBackend {
public:
    KernelTimer(std::unique_ptr<BuoyancyBackend> inner, std::shared_ptr<double> total)
        : inner_(std::move(inner)), total_(std::move(total)) {}
    BackendKind kind() const override { return inner_->kind(); }
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
    std::size_t addExchangeSet(std::span<const ExchangeSample> samples,
                               std::size_t nodes) override {
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

Result<PreviewSession::Built> PreviewSession::build(const Scene& scene, const std::string& device) {
    // The preview panel shows the device's kernel time, which needs the profiling events.
    Result<std::unique_ptr<BuoyancyBackend>> backend =
        createBuoyancyBackend(device, nullptr, OpenClOptions{.deviceTimings = true});
    if (!backend) return backend.error();
    auto total = std::make_shared<double>(0.0);
    Result<std::unique_ptr<World>> world =
        World::create(scene, std::make_unique<KernelTimer>(std::move(*backend), total));
    if (!world) return world.error();
    return Built{std::move(*world), std::move(total)};
}

Result<std::unique_ptr<PreviewSession>> PreviewSession::create(Scene scene,
                                                               const std::string& device) {
    if (scene.bodies.empty()) {
        return makeError(ErrorKind::invalidArgument, "the live preview needs at least one body");
    }
    std::unique_ptr<PreviewSession> session(new PreviewSession());
    session->scene_ = std::move(scene);
    session->device_ = device;
    Result<Built> built = build(session->scene_, device);
    if (!built) return built.error();
    session->world_ = std::move(built->world);
    session->kernelTotalMs_ = std::move(built->kernelTotalMs);
    return session;
}

int PreviewSession::textureSize() const { return scene_.bodies.front().desc.textureSize; }

int PreviewSession::rebuildingSize() const { return pending_ ? pending_->size : 0; }

double PreviewSession::rebuildProgress() const {
    return pending_ ? pending_->progress.load() : 0.0;
}

std::size_t PreviewSession::coveredTexels() const {
    std::size_t n = 0;
    for (const SimulatedBody& b : world_->bodies()) n += b.textures.coveredCount();
    return n;
}

void PreviewSession::setTimeScale(double scale) {
    timeScale_ = std::clamp(std::isfinite(scale) ? scale : 1.0, 0.01, 10.0);
}

void PreviewSession::setWater(const WaterModel& water) {
    scene_.water = water;
    world_->setWater(water);
}

void PreviewSession::setIntegrator(Integrator integrator) {
    scene_.simulation.integrator = integrator;
    world_->setIntegrator(integrator);
}

void PreviewSession::requestTextureSize(int size, std::optional<std::size_t> onlyBody) {
    cancelRebuild();
    auto job = std::make_unique<RebuildJob>();
    job->size = size;
    job->scene = scene_;
    job->thread = std::thread([job = job.get(), device = device_, onlyBody] {
        lowerThisThreadsPriority();
        // The same parts (meshes, frames, graphs, maps) baked again at the new size; the
        // progress is the bodies done plus the share of the one baking.
        const std::size_t count = job->scene.bodies.size();
        for (std::size_t b = 0; b < count && !job->error; ++b) {
            if (onlyBody && b != *onlyBody) continue;  // kept as it runs
            SceneBody& body = job->scene.bodies[b];
            body.desc.textureSize = job->size;
            BakeControl control;
            control.progress = [job, b, count](double fraction) {
                job->progress = (static_cast<double>(b) + fraction) / static_cast<double>(count);
            };
            control.cancelled = [job] { return job->cancel.load(); };
            Result<SceneBody> rebaked = bakeSceneBody(body.desc, body.parts, control);
            if (rebaked)
                body = std::move(*rebaked);
            else
                job->error = rebaked.error();
        }
        if (!job->error && !job->cancel) {
            Result<Built> built = build(job->scene, device);
            if (built)
                job->built = std::move(*built);
            else
                job->error = built.error();
        }
        job->done = true;
    });
    pending_ = std::move(job);
}

void PreviewSession::cancelRebuild() {
    reapAbandoned();
    if (!pending_) return;
    pending_->cancel = true;
    abandoned_.push_back(std::move(pending_));
}

void PreviewSession::reapAbandoned() {
    std::erase_if(abandoned_, [](std::unique_ptr<RebuildJob>& job) {
        if (!job->done) return false;
        job->thread.join();  // finished: returns at once
        return true;
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
    installForces();
    return Ok{};
}

Status PreviewSession::swapInRebuilt(RebuildJob& job) {
    if (job.error) {
        rebuildError_ = job.error->message;
        return *job.error;
    }
    rebuildError_.clear();
    // The rebaked bodies; the water and integrator as they are now (changed meanwhile or not).
    scene_.bodies = std::move(job.scene.bodies);
    job.built.world->setWater(scene_.water);
    job.built.world->setIntegrator(scene_.simulation.integrator);
    return swapIn(std::move(job.built));
}

void PreviewSession::pollRebuild() {
    reapAbandoned();
    if (!pending_ || !pending_->done) return;
    std::unique_ptr<RebuildJob> job = std::move(pending_);
    job->thread.join();
    (void)swapInRebuilt(*job);  // a failure is kept in rebuildError_
}

Status PreviewSession::finishRebuild() {
    if (!pending_) return Ok{};
    std::unique_ptr<RebuildJob> job = std::move(pending_);
    job->thread.join();
    return swapInRebuilt(*job);
}

Status PreviewSession::advance() {
    pollRebuild();
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
    if (grabbedBody_ && steps > 0 && scene_.simulation.integrator != Integrator::RK4) {
        grabImpulse_ += grabForceSum_ * (scene_.simulation.timeStep / static_cast<double>(steps));
    }
    record();
    return Ok{};
}

Status PreviewSession::step() { return advance(); }

Result<int> PreviewSession::update(double wallSeconds) {
    pollRebuild();  // paused too: a new texture size arrives when it is baked, not on Play
    if (!playing_) {
        timings_.framesLastUpdate = 0;
        return 0;
    }
    const double frame = scene_.simulation.timeStep;
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
                .count() > updateBudgetMs_)
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
    // A fresh world from the scene as it stands (with the settings changed while running):
    // the starting states, time 0 and full water graphs. A pending rebake carries on and
    // swaps in when done, as it would have without the reset.
    Result<Built> built = build(scene_, device_);
    if (!built) return built.error();
    world_ = std::move(built->world);
    kernelTotalMs_ = std::move(built->kernelTotalMs);
    checkBackend_.reset();
    checkIds_.clear();
    accumulator_ = 0;
    grabbedBody_.reset();
    grabImpulse_ = Eigen::Vector3d::Zero();
    installForces();  // the floor's contact
    history_.time.clear();
    history_.series.clear();
    timings_ = {};
    return Ok{};
}

Status PreviewSession::grab(std::size_t body, const Eigen::Vector3d& objectPoint,
                            const Eigen::Vector3d& target, double stiffness) {
    if (body >= world_->bodies().size()) {
        return makeError(ErrorKind::invalidArgument, "grab: no body " + std::to_string(body));
    }
    const double mass = world_->bodies()[body].mass.mass;
    const double omega = 2.0 * std::numbers::pi * kGrabFrequencyHz;
    grabStiffness_ = stiffness > 0 ? stiffness : mass * omega * omega;
    grabDamping_ = 2.0 * std::sqrt(grabStiffness_ * mass);  // critical for the body's mass
    const std::optional<std::size_t> previous = grabbedBody_;
    grabbedBody_ = body;
    grabObjectPoint_ = objectPoint;
    grabTarget_ = target;
    grabImpulse_ = Eigen::Vector3d::Zero();
    // Setting a body's force wakes it: only the bodies whose spring changes are told, so that
    // a grab wakes the grabbed body and leaves every other sleeper asleep.
    if (previous && *previous != body) installSpring(*previous);
    installSpring(body);
    return Ok{};
}

void PreviewSession::installSpring(std::size_t body) {
    ExternalForce spring;
    if (grabbedBody_ == body) {
        spring = [this](const SimulatedBody& b, const RigidBodyState& s) {
            const Wrench w =
                springWrench(b, s, grabObjectPoint_, grabTarget_, grabStiffness_, grabDamping_);
            grabForceSum_ += w.force;
            return w;
        };
    }
    (void)world_->setExternalForce(body, std::move(spring));
}

void PreviewSession::installForces() {
    const std::optional<double> floor = floorHeight();
    if (floor && hullPoints_.size() != scene_.bodies.size()) {
        // The hull's vertices once, without repeats (a flat-shaded mesh repeats each corner).
        hullPoints_.assign(scene_.bodies.size(), {});
        for (std::size_t b = 0; b < scene_.bodies.size(); ++b) {
            const auto& mesh = scene_.bodies[b].parts.mesh;
            if (!mesh) continue;
            std::vector<Eigen::Vector3d> points(mesh->positions.begin(), mesh->positions.end());
            std::sort(points.begin(), points.end(), [](const auto& a, const auto& c) {
                return std::lexicographical_compare(a.data(), a.data() + 3, c.data(), c.data() + 3);
            });
            points.erase(std::unique(points.begin(), points.end()), points.end());
            hullPoints_[b] = std::move(points);
        }
    }
    for (std::size_t body = 0; body < world_->bodies().size(); ++body) {
        // The floor is a resting contact (a body lying on it may sleep), the spring a push.
        const std::vector<Eigen::Vector3d>* hull =
            floor && body < hullPoints_.size() ? &hullPoints_[body] : nullptr;
        ExternalForce contact;
        if (hull) {
            contact = [hull, floorY = *floor, friction = seaFloor_.friction](
                          const SimulatedBody& b, const RigidBodyState& s) {
                return floorContactWrench(b, s, *hull, floorY, friction);
            };
        }
        (void)world_->setContactForce(body, std::move(contact));
        installSpring(body);
    }
}

namespace {

bool samePixels(const PaintedMap* a, const PaintedMap* b) {
    if (!a || !b) return a == b;
    return a->width == b->width && a->height == b->height && a->values == b->values;
}

}  // namespace

Status PreviewSession::setBodyPaint(std::size_t body, const MaterialDesc& material,
                                    std::shared_ptr<const PaintedMap> permeability,
                                    std::shared_ptr<const PaintedMap> shellDensity,
                                    std::shared_ptr<const PaintedMap> shellThickness) {
    if (body >= scene_.bodies.size() || body >= world_->bodies().size()) {
        return makeError(ErrorKind::invalidArgument,
                         "setBodyPaint: no body " + std::to_string(body));
    }
    SceneBody& b = scene_.bodies[body];
    const bool seeps = !samePixels(b.parts.permeabilityMap.get(), permeability.get());
    b.desc.material = material;
    b.parts.shellDensityMap = shellDensity;
    b.parts.shellThicknessMap = shellThickness;
    b.parts.permeabilityMap = std::move(permeability);
    if (!seeps)
        return world_->setMaterial(body, material, std::move(shellDensity),
                                   std::move(shellThickness));
    return rebuildCarryingWater(std::nullopt, nullptr);
}

Status PreviewSession::rebuildCarryingWater(std::optional<std::size_t> body,
                                            std::shared_ptr<const WaterGraph> graphNow) {
    // The graphs as they are now: the new world starts with the water the running one holds.
    Scene next = scene_;
    for (std::size_t i = 0; i < next.bodies.size() && i < world_->bodies().size(); ++i) {
        if (body && i == *body) {
            next.bodies[i].parts.waterGraph = graphNow;
        } else if (const WaterGraphSimulation* graph = world_->waterGraph(i); graph) {
            next.bodies[i].parts.waterGraph = std::make_shared<const WaterGraph>(graph->graph());
        }
    }
    Result<Built> built = build(next, device_);
    if (!built) return built.error();
    built->world->setWater(scene_.water);
    built->world->setIntegrator(scene_.simulation.integrator);
    return swapIn(std::move(*built));
}

Status PreviewSession::checkEditedGraph(std::size_t body, const std::optional<WaterGraph>& graph) {
    std::string& problem = graphProblems_[body];
    problem.clear();
    if (!graph) return Ok{};
    const GraphReport report = validateGraph(*graph);
    for (const GraphProblem& p : report.problems) {
        if (p.error) problem += (problem.empty() ? "" : "; ") + p.message;
    }
    if (problem.empty()) return Ok{};
    return makeError(ErrorKind::invalidArgument,
                     scene_.bodies[body].label + ": the edited water graph is not simulated (" +
                         problem + "); the preview runs the last valid one until it is fixed");
}

Status PreviewSession::setBodyGraph(std::size_t body, const std::optional<WaterGraph>& before,
                                    const std::optional<WaterGraph>& after,
                                    const std::optional<WaterGraphDesc>& settings) {
    if (body >= scene_.bodies.size() || body >= world_->bodies().size()) {
        return makeError(ErrorKind::invalidArgument,
                         "setBodyGraph: no body " + std::to_string(body));
    }
    // A graph the World cannot run (a pipe to a missing node, no nodes, ...) is held back, and
    // said: the running graph stays until the edits make a valid one.
    graphProblems_.resize(scene_.bodies.size());
    if (Status valid = checkEditedGraph(body, after); !valid) return valid;
    SceneBody& b = scene_.bodies[body];
    // The nodes the scene added to the document's graph (the spaces behind an open hull's
    // caps) stay as they are: the document never had them.
    const auto ownNode = [&](const std::string& id) { return before && before->indexOf(id) >= 0; };
    std::vector<GraphNode> added;
    if (b.parts.waterGraph) {
        for (const GraphNode& node : b.parts.waterGraph->nodes)
            if (!ownNode(node.id)) added.push_back(node);
    }
    std::optional<WaterGraph> start = after;
    if (!added.empty()) {
        if (!start) start.emplace();
        start->nodes.insert(start->nodes.end(), added.begin(), added.end());
    }
    // What each node holds now: the running world's water for a node it has, unless the edit
    // set the node's water (then the new value), within the node's new capacity.
    std::shared_ptr<const WaterGraph> now;
    if (start) {
        WaterGraph running = *start;
        const WaterGraphSimulation* sim = world_->waterGraph(body);
        for (GraphNode& node : running.nodes) {
            const int was = sim ? sim->graph().indexOf(node.id) : -1;
            if (was < 0) continue;
            const int doc = before ? before->indexOf(node.id) : -1;
            const bool waterEdited = doc >= 0 && after && after->indexOf(node.id) >= 0 &&
                                     before->nodes[std::size_t(doc)].water != node.water;
            if (waterEdited) continue;
            node.water = std::min(sim->graph().nodes[std::size_t(was)].water, node.capacity);
        }
        now = std::make_shared<const WaterGraph>(std::move(running));
    }
    // Reset starts from the edited graph: the scene keeps it with its starting water.
    b.parts.waterGraph = start ? std::make_shared<const WaterGraph>(std::move(*start)) : nullptr;
    if (settings)
        b.desc.waterGraph = settings;
    else if (!b.parts.waterGraph)
        b.desc.waterGraph.reset();
    else if (!b.desc.waterGraph)
        b.desc.waterGraph.emplace();
    return rebuildCarryingWater(body, std::move(now));
}

Result<std::vector<std::size_t>> PreviewSession::followDocument(const Document& document) {
    std::vector<std::size_t> changed;
    const std::size_t count = std::min(document.bodyCount(), scene_.bodies.size());
    auto copyOf = [](const PaintedMap* map) {
        return map ? std::make_shared<const PaintedMap>(*map) : nullptr;
    };
    const bool first = paintSeen_.empty();
    paintSeen_.resize(count);
    std::string stale;
    std::string held;  // the graphs held back, why
    for (std::size_t b = 0; b < count; ++b) {
        PaintSeen& seen = paintSeen_[b];
        const BodyDesc& desc = document.project().bodies[b];
        const WaterGraph* graph = document.graph(b);
        const bool graphSame = seen.graph.has_value() == (graph != nullptr) &&
                               (!graph || *seen.graph == *graph) &&
                               seen.graphSettings == desc.waterGraph;
        if (first || !graphSame) {
            // The graph seen is the one running: one held back is tried again at each edit.
            std::optional<WaterGraph> edited =
                graph ? std::optional<WaterGraph>(*graph) : std::nullopt;
            if (!first) {
                if (Status s = setBodyGraph(b, seen.graph, edited, desc.waterGraph); !s.ok()) {
                    held += (held.empty() ? "" : "\n") + s.error().message;
                    edited = seen.graph;
                } else {
                    changed.push_back(b);
                }
            }
            seen.graph = std::move(edited);
            seen.graphSettings = desc.waterGraph;
        }
        const MaterialDesc& material = desc.material;
        const PaintedMap* permeability = document.map(b, MapChannel::Permeability);
        const PaintedMap* density = document.map(b, MapChannel::Density);
        const PaintedMap* thickness = document.map(b, MapChannel::Thickness);
        if (!first && seen.material == material &&
            samePixels(seen.permeability.get(), permeability) &&
            samePixels(seen.shellDensity.get(), density) &&
            samePixels(seen.shellThickness.get(), thickness)) {
            continue;
        }
        // The scene took the document's pixels as they were (not moved onto a repaired solid)
        // when its maps are the ones last seen.
        const SceneBody& body = scene_.bodies[b];
        const bool direct =
            samePixels(body.parts.permeabilityMap.get(), seen.permeability.get()) &&
            samePixels(body.parts.shellDensityMap.get(), seen.shellDensity.get()) &&
            samePixels(body.parts.shellThicknessMap.get(), seen.shellThickness.get());
        seen.material = material;
        seen.permeability = copyOf(permeability);
        seen.shellDensity = copyOf(density);
        seen.shellThickness = copyOf(thickness);
        if (first) continue;
        if (!direct) {
            stale += (stale.empty() ? "" : ", ") + body.label;
            continue;
        }
        if (Status s = setBodyPaint(b, material, seen.permeability, seen.shellDensity,
                                    seen.shellThickness);
            !s.ok())
            return s.error();
        if (changed.empty() || changed.back() != b) changed.push_back(b);
    }
    if (!stale.empty()) {
        held += (held.empty() ? "" : "\n") + stale +
                ": painted over a repaired solid; restart the preview to use the new paint";
    }
    if (!held.empty()) return makeError(ErrorKind::invalidArgument, held);
    return changed;
}

void PreviewSession::setSeaFloor(const SeaFloor& floor) {
    seaFloor_ = floor;
    if (!(seaFloor_.depth > 0) || !std::isfinite(seaFloor_.depth))
        seaFloor_.depth = SeaFloor::kDefaultDepth;
    installForces();
}

std::optional<double> PreviewSession::floorHeight() const {
    if (!seaFloor_.enabled) return std::nullopt;
    return scene_.water.level - seaFloor_.depth;
}

double PreviewSession::lowestPoint(std::size_t body) const {
    const SimulatedBody& b = world_->bodies().at(body);
    const auto& mesh = scene_.bodies.at(body).parts.mesh;
    const Pose pose = b.pose();
    double lowest = std::numeric_limits<double>::infinity();
    if (mesh) {
        for (const Eigen::Vector3d& q : mesh->positions)
            lowest = std::min(lowest, pose.rotation.row(1).dot(q) + pose.translation.y());
    }
    return lowest;
}

void PreviewSession::release() {
    if (!grabbedBody_) return;
    const std::size_t body = *grabbedBody_;
    grabbedBody_.reset();
    installSpring(body);  // the others keep sleeping
}

Eigen::Vector3d PreviewSession::grabPoint() const {
    if (!grabbedBody_) return Eigen::Vector3d::Zero();
    return world_->bodies()[*grabbedBody_].pose().apply(grabObjectPoint_);
}

Result<SubmergedVolumeCheck> PreviewSession::volumeCheck(std::size_t i) {
    if (i >= world_->bodies().size()) {
        return makeError(ErrorKind::invalidArgument, "volume check: no body " + std::to_string(i));
    }
    if (!checkBackend_) {
        Result<std::unique_ptr<BuoyancyBackend>> backend = createBuoyancyBackend(device_);
        if (!backend) return backend.error();
        checkBackend_ = std::move(*backend);
        checkIds_.assign(world_->bodies().size(), SIZE_MAX);
    }
    const SimulatedBody& body = world_->bodies()[i];
    if (checkIds_[i] == SIZE_MAX) {
        checkIds_[i] = checkBackend_->addBody(body.textures, body.backendCenter);
    }
    // The exact clip of the mesh the world baked (its atlas applied).
    const TriangleMesh& mesh = *world_->scene().bodies[i].parts.mesh;
    BodyFrame frame;
    frame.pose = body.pose();
    frame.centerOfMass = body.backendCenter;
    frame.time = world_->time();
    return checkSubmergedVolume(*checkBackend_, checkIds_[i], mesh, frame, scene_.water.level,
                                body.fluid);
}

void PreviewSession::record() {
    const std::vector<SimulatedBody>& bodies = world_->bodies();
    std::vector<std::pair<std::string, std::pair<std::string, double>>> row;
    const Eigen::Vector3d gravity = scene_.simulation.gravity;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const SimulatedBody& b = bodies[i];
        const std::string name = b.name.empty() ? "body " + std::to_string(i) : b.name;
        const Eigen::Vector2d ht = heelAndTrimDegrees(b.state.orientation.toRotationMatrix());
        const bool flat = scene_.water.kind == WaterModel::Kind::Flat;
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
    for (std::size_t k = 0; same && k < row.size(); ++k)
        same = history_.series[k].name == row[k].first;
    if (!same) {
        history_.time.clear();
        history_.series.clear();
        for (const auto& [name, value] : row) history_.series.push_back({name, value.first, {}});
    }
    if (history_.time.size() >= history_.capacity) {
        const std::size_t drop = history_.capacity / 10 + 1;  // amortised: not one per frame
        history_.time.erase(history_.time.begin(), history_.time.begin() + drop);
        for (PlotSeries& s : history_.series)
            s.values.erase(s.values.begin(), s.values.begin() + drop);
    }
    history_.time.push_back(world_->time());
    for (std::size_t k = 0; k < row.size(); ++k)
        history_.series[k].values.push_back(row[k].second.second);
}

}  // namespace plimsoll::editor
