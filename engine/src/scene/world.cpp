// World stepping (world.h).
#include "plimsoll/scene/world.h"

#include "plimsoll/surface/deform.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/physics/cummins.h"
#include "plimsoll/scene/scene_radiation.h"

#include "plimsoll_eval/levels.hpp"

#include <algorithm>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace plimsoll {

/// The frames of a deforming body and the piece table its bake recorded (deform.h).
struct World::Deformation {
    std::shared_ptr<const std::vector<TriangleMesh>> frames;
    std::shared_ptr<const SurfacePieceTable> pieces;
    double framesPerSecond = 24.0;
    std::size_t currentFrame = 0;
};

/// The water graph of a hollow or permeable body (graph.h) and the body's own mass without it.
struct World::Flooding {
    WaterGraphSimulation graph;
    MassProperties hull;    ///< the body without its water
    double hullRadius = 0;  ///< bounding radius about hull.centerOfMass, m
    Eigen::Matrix3d composedAt = Eigen::Matrix3d::Identity();  ///< rotation last composed at
    std::size_t exchangeSet = 0;  ///< the permeable samples' id in the backend
    ExchangeSums rates;           ///< the last exchange pass, per node
};

/// A body with radiation: its model, the memory's filters, and what the current step uses.
struct World::Radiating {
    std::shared_ptr<const BodyRadiation> radiation;
    MemoryState memory;
    double share = 0;     ///< entrainedShare at the start of the step
    Wrench memoryWrench;  ///< world axes, about the centre of mass, for the current step
};

/// The level ladder of a body (level_ladder.h): every level registered with the backend, the
/// one in use, and the blend of a switch.
struct World::Detail {
    std::shared_ptr<const std::vector<BuoyancyLevel>> levels;
    std::vector<std::size_t> ids;    ///< backend id per level; the finest is the body's own
    plimsoll_eval::LevelSwitch lod;  ///< level in use, hold and blend (plimsoll_eval/levels.hpp)
    BuoyancyResult offset;           ///< the old level's result minus the new one's, at the switch
};

namespace {

/// r += w d, field by field (what a level's blend adds).
void addScaled(BuoyancyResult& r, const BuoyancyResult& d, double w) {
    r.submergedVolume += w * d.submergedVolume;
    r.centerOfBuoyancy += w * d.centerOfBuoyancy;
    r.force += w * d.force;
    r.torque += w * d.torque;
    r.pressureForce += w * d.pressureForce;
    r.pressureTorque += w * d.pressureTorque;
    r.dragForce += w * d.dragForce;
    r.dragTorque += w * d.dragTorque;
    r.wettedArea += w * d.wettedArea;
}

MassDistribution toDistribution(const MassProperties& p) {
    MassDistribution m;
    m.mass = p.mass;
    m.inertia = p.inertia;
    m.centerOfMass = p.centerOfMass;
    return m;
}

double boundingRadiusAbout(const SurfaceTextures& textures, const Eigen::Vector3d& centre) {
    double radius = 0;
    for (std::size_t i = 0; i < textures.coveredCount(); ++i) {
        // Half a texel's extent beyond its centroid: the surface it stands for.
        radius = std::max(
            radius, (textures.position[i] - centre).norm() + 0.5 * std::sqrt(textures.area[i]));
    }
    return radius;
}

}  // namespace

World::World(Scene scene, std::unique_ptr<BuoyancyBackend> backend, LogFunction log)
    : scene_(std::move(scene)), backend_(std::move(backend)), log_(std::move(log)) {}

World::~World() = default;

void World::say(const std::string& line) const {
    if (log_) log_(line);
}

Status World::withBackend(const std::function<Status(BuoyancyBackend&)>& call) {
    Status status = call(*backend_);
    if (status.ok() || fellBack_ || !isOpenCl(backend_->kind())) return status;
    // The reference backend needs nothing from the device: every body's textures are here.
    say(status.error().message + ": continuing on the C++ reference backend");
    std::unique_ptr<BuoyancyBackend> reference = createReferenceBackend();
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        SimulatedBody& body = bodies_[i];
        body.backendId = reference->addBody(body.textures, body.backendCenter);
        if (Detail* d = details_[i].get()) {
            for (std::size_t k = 0; k + 1 < d->ids.size(); ++k)
                d->ids[k] = reference->addBody(*(*d->levels)[k].textures, body.backendCenter);
            d->ids.back() = body.backendId;
            body.backendId = d->ids[static_cast<std::size_t>(d->lod.level)];
        }
    }
    for (const std::unique_ptr<Flooding>& f : floodings_) {
        if (f)
            f->exchangeSet =
                reference->addExchangeSet(f->graph.samples(), f->graph.graph().nodes.size());
    }
    backend_ = std::move(reference);
    fellBack_ = true;
    return call(*backend_);
}

Result<std::unique_ptr<World>> World::create(Scene scene, std::unique_ptr<BuoyancyBackend> backend,
                                             LogFunction log) {
    if (Status s = checkGravity(scene.simulation.gravity); !s) return s.error();
    // The waves' dispersion relation takes the scene's one gravity, as everything else does.
    scene.water.gravity = scene.simulation.gravity.norm();
    std::unique_ptr<World> world(new World(std::move(scene), std::move(backend), std::move(log)));
    for (const SceneBody& body : world->scene_.bodies) {
        if (Status s = world->addBody(body); !s.ok()) return s.error();
    }
    // A body no affordable step resolves is refused before anything runs.
    if (Result<int> subSteps = world->subStepsFor(world->scene_.simulation.timeStep); !subSteps)
        return subSteps.error();
    return world;
}

Status World::addBody(const SceneBody& scene) {
    const BodyDesc& desc = scene.desc;
    const std::string& label = scene.label;
    if (!scene.parts.mesh || !scene.textures || !scene.mass) {
        return makeError(ErrorKind::invalidArgument, label + ": not baked (bakeSceneBody)");
    }
    std::unique_ptr<Deformation> deformation;
    if (desc.deforms()) {
        if (!scene.parts.frames || !scene.pieces) {
            return makeError(ErrorKind::invalidArgument, label + ": deforms, but has no frames");
        }
        deformation = std::make_unique<Deformation>();
        deformation->frames = scene.parts.frames;
        deformation->pieces = scene.pieces;
        deformation->framesPerSecond = desc.framesPerSecond;
    }
    const MassProperties& props = *scene.mass;
    const Eigen::Vector3d& gravity = scene_.simulation.gravity;

    SimulatedBody body;
    body.name = desc.name;
    body.mass = toDistribution(props);
    body.volume = props.volume;
    body.backendCenter = props.centerOfMass;
    body.boundingRadius = boundingRadiusAbout(*scene.textures, body.mass.centerOfMass);
    const Pose start = Pose::fromEulerDegrees(desc.position, desc.rotationDegrees);
    std::unique_ptr<Flooding> flooding;
    if (desc.waterGraph) {
        Result<std::unique_ptr<Flooding>> made = makeFlooding(scene);
        if (!made) return made.error();
        flooding = std::move(*made);
        flooding->exchangeSet = backend_->addExchangeSet(flooding->graph.samples(),
                                                         flooding->graph.graph().nodes.size());
        flooding->hullRadius = body.boundingRadius;
        flooding->composedAt = start.rotation;
        const MassProperties full = flooding->graph.compose(props, start.rotation);
        body.mass = toDistribution(full);
        body.boundingRadius += (full.centerOfMass - props.centerOfMass).norm();
        body.water = flooding->graph.storedWater();
    } else if (scene.parts.permeabilityMap) {
        say(label + ": has a permeability map but no water graph: sealed, no water enters");
    }
    body.textures = *scene.textures;
    body.deforms = desc.deforms();
    body.fluid.density = scene_.medium.density;
    body.fluid.gravity = gravity.norm();
    body.fluid.dragCoefficient = desc.dragCoefficient;
    body.fluid.frictionCoefficient = desc.frictionCoefficient;
    Motion motion;
    motion.linear = desc.velocity;
    motion.angular = desc.angularVelocity;
    body.state = stateAt(start, body.mass, motion);
    std::unique_ptr<Radiating> radiating;
    if (desc.radiationRequired() && !scene.radiation) {
        return makeError(ErrorKind::invalidArgument,
                         label + ": radiation is on but was not computed (computeBodyRadiation)");
    }
    // On by default wherever it was computed (the scene loader computes it for every rigid body
    // that floats unless the project turns it off); the stand-in damping follows.
    const bool radiates = desc.radiates() && scene.radiation;
    body.linearDamping = desc.standInLinearDamping(radiates);
    body.verticalDamping = desc.standInVerticalDamping(radiates);
    body.angularDamping = desc.standInAngularDamping(radiates);
    if (radiates) {
        radiating = std::make_unique<Radiating>();
        radiating->radiation = scene.radiation;
        const CumminsModel& model = scene.radiation->model;
        radiating->memory = memoryStateFor(model);
        // The added mass the body starts with, so that it starts with the velocities asked for.
        BodyFrame frame;
        frame.pose = start;
        frame.centerOfMass = body.mass.centerOfMass;
        const double submerged =
            outOfWater(body, body.state)
                ? 0.0
                : evaluateBuoyancyReference(*scene.textures, frame, scene_.water, body.fluid)
                      .submergedVolume;
        radiating->share = entrainedShare(submerged, scene.radiation->restVolume);
        applyAddedMass(model, radiating->share, body.mass, body.state);
        body.state = stateAt(start, body.mass, motion);
        std::size_t states = 0;
        for (const auto& mode : model.memory) states += 2 * mode.size();
        std::ostringstream note;
        note << label << ": radiation over " << scene.radiation->panelCount
             << " panels, heave added mass " << model.addedMassInfinity(kHeaveY, kHeaveY)
             << " kg at infinite frequency, " << states << " memory states"
             << (body.linearDamping > 0 || body.angularDamping > 0
                     ? "; linear_damping and angular_damping still apply (0 leaves "
                       "the damping to radiation and drag)"
                     : "");
        say(note.str());
    }
    body.backendId = backend_->addBody(body.textures, body.backendCenter);
    body.levelSize = desc.textureSize;
    std::unique_ptr<Detail> detail;
    if (scene.levels && scene.levels->size() > 1 && !flooding && !deformation) {
        // Every level is registered now: a switch costs no upload. The finest is the body's own.
        detail = std::make_unique<Detail>();
        detail->levels = scene.levels;
        std::ostringstream note;
        note << label << ": level ladder";
        for (std::size_t k = 0; k < scene.levels->size(); ++k) {
            const BuoyancyLevel& level = (*scene.levels)[k];
            detail->ids.push_back(k + 1 < scene.levels->size()
                                      ? backend_->addBody(*level.textures, body.backendCenter)
                                      : body.backendId);
            note << (k ? ", " : " ") << level.size << "^2 (force error " << level.forceError
                 << " of rho g V, " << level.evaluationUs << " us)";
        }
        detail->lod.level = static_cast<int>(scene.levels->size()) - 1;
        detail->lod.framesHeld = std::numeric_limits<int>::max() / 2;  // free to switch at once
        say(note.str());
    } else if (scene.levels && (flooding || deformation)) {
        say(label + ": keeps its own level (" + std::to_string(desc.textureSize) +
            "^2): a deforming body or one with a water graph does not switch levels");
    }
    std::ostringstream line;
    line << label << ": " << body.textures.coveredCount() << " samples at " << desc.textureSize
         << "^2, mass " << body.mass.mass << " kg, volume " << body.volume << " m^3"
         << (body.deforms ? ", deforming: mass recomputed as it changes"
                          : ", rigid: mass properties computed once");
    say(line.str());
    bodies_.push_back(std::move(body));
    deformations_.push_back(std::move(deformation));
    floodings_.push_back(std::move(flooding));
    radiatings_.push_back(std::move(radiating));
    details_.push_back(std::move(detail));
    materials_.push_back(desc.material);
    shellDensityMaps_.push_back(scene.parts.shellDensityMap);
    shellThicknessMaps_.push_back(scene.parts.shellThicknessMap);
    sleep_.emplace_back();
    changedLastFrame_.push_back(0);
    return Ok{};
}

Result<std::unique_ptr<World::Flooding>> World::makeFlooding(const SceneBody& body) const {
    const BodyDesc& desc = body.desc;
    const std::string& label = body.label;
    const WaterGraphDesc& g = *desc.waterGraph;
    if (!body.parts.waterGraph) {
        return makeError(ErrorKind::invalidArgument, label + ": water graph named but none given");
    }
    const WaterGraph& graph = *body.parts.waterGraph;
    std::vector<double> permeability;
    if (body.parts.permeabilityMap) {
        permeability = sampleAtTexels(*body.parts.permeabilityMap, *body.textures, g.permeability);
    }
    GraphSettings settings = g.settings;
    settings.density = scene_.medium.density;
    settings.viscosity = scene_.medium.viscosity;
    settings.gravity = scene_.simulation.gravity.norm();
    Result<WaterGraphSimulation> sim =
        WaterGraphSimulation::create(graph, *body.textures, permeability, settings);
    if (!sim) return withContext(label + ": water graph: ", sim.error());
    std::ostringstream line;
    line << label << ": water graph " << (g.graph.empty() ? "of its openings" : g.graph) << ": "
         << graph.nodes.size() << " nodes, " << graph.pipes.size() << " pipes, capacity "
         << graph.totalCapacity() << " m^3, " << sim->samples().size() << " permeable samples, "
         << flowModelName(settings.flow) << " flow"
         << (settings.freeSurface ? ", free surface" : "");
    say(line.str());
    if (graph.nodes.size() > kMaxExchangeNodes) {
        return makeError(ErrorKind::limit,
                         label + ": water graph: " + std::to_string(graph.nodes.size()) +
                             " nodes; at most " + std::to_string(kMaxExchangeNodes));
    }
    return std::make_unique<Flooding>(
        Flooding{std::move(*sim), *body.mass, 0.0, Eigen::Matrix3d::Identity(), 0, {}});
}

const BodyRadiation* World::radiation(std::size_t body) const {
    return body < radiatings_.size() && radiatings_[body] ? radiatings_[body]->radiation.get()
                                                          : nullptr;
}

void World::startRadiationStep(std::size_t i, double submergedVolume) {
    Radiating* r = radiatings_[i].get();
    if (!r) return;
    SimulatedBody& body = bodies_[i];
    const CumminsModel& model = r->radiation->model;
    r->share = entrainedShare(submergedVolume, r->radiation->restVolume);
    applyAddedMass(model, r->share, body.mass, body.state);
    // The memory's force, body axes, scaled by the share like its input (finishRadiationStep).
    const Vector6d force = r->share * memoryForce(model, r->memory);
    const Eigen::Matrix3d rotation = body.state.orientation.toRotationMatrix();
    r->memoryWrench.force = rotation * force.head<3>();
    r->memoryWrench.torque = rotation * force.tail<3>();
}

void World::finishRadiationStep(std::size_t i, double dt) {
    Radiating* r = radiatings_[i].get();
    if (!r) return;
    const SimulatedBody& body = bodies_[i];
    const Eigen::Matrix3d toBody = body.state.orientation.toRotationMatrix().transpose();
    Vector6d velocity;
    velocity << toBody * linearVelocity(body.state, body.mass),
        toBody * angularVelocity(body.state, body.mass);
    advanceMemory(r->radiation->model, r->memory, r->share * velocity, dt);
}

const WaterGraphSimulation* World::waterGraph(std::size_t body) const {
    return body < floodings_.size() && floodings_[body] ? &floodings_[body]->graph : nullptr;
}

BodyRequest World::requestFor(const SimulatedBody& body, const RigidBodyState& state,
                              double time) const {
    BodyRequest request;
    request.body = body.backendId;
    request.fluid = body.fluid;
    request.frame.pose = poseOf(state, body.mass);
    request.frame.motion.linear = linearVelocity(state, body.mass);
    request.frame.motion.angular = angularVelocity(state, body.mass);
    request.frame.centerOfMass = body.backendCenter;
    request.frame.time = time;
    if (body.backendCenter != body.mass.centerOfMass) {
        // The backend's centre is not the centre of mass (the body holds water): its velocity.
        const Eigen::Vector3d r =
            request.frame.pose.rotation * (body.backendCenter - body.mass.centerOfMass);
        request.frame.motion.linear += request.frame.motion.angular.cross(r);
    }
    return request;
}

void World::toCenterOfMass(const SimulatedBody& body, const RigidBodyState& state,
                           BuoyancyResult& result) const {
    if (body.backendCenter == body.mass.centerOfMass) return;
    // Torques about the backend's centre c moved to the centre of mass: + (c - com) x F.
    const Eigen::Vector3d r =
        poseOf(state, body.mass).rotation * (body.backendCenter - body.mass.centerOfMass);
    result.torque += r.cross(result.force);
    result.pressureTorque += r.cross(result.pressureForce);
    result.dragTorque += r.cross(result.dragForce);
}

void World::replaceMass(std::size_t i, const MassProperties& props) {
    SimulatedBody& body = bodies_[i];
    // The pose stays; the velocities stay (the water moves with the body): the new centre of
    // mass moves with v + w x (c_new - c_old).
    const Pose pose = body.pose();
    Motion motion;
    motion.linear = linearVelocity(body.state, body.mass);
    motion.angular = angularVelocity(body.state, body.mass);
    const Eigen::Vector3d oldCenter = body.state.position;
    const MassDistribution old = body.mass;
    body.mass = toDistribution(props);
    body.mass.addedMass = old.addedMass;  // the water around the body did not change
    body.mass.addedInertia = old.addedInertia;
    const Eigen::Vector3d newCenter = pose.apply(body.mass.centerOfMass);
    motion.linear += motion.angular.cross(newCenter - oldCenter);
    body.state = stateAt(pose, body.mass, motion);
}

Status World::stepWaterGraphs(double frameTime) {
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        Flooding* f = floodings_[i].get();
        // A sleeping body's water stays: nothing moves it until the body wakes.
        if (!f || bodies_[i].asleep) continue;
        SimulatedBody& body = bodies_[i];
        const Pose pose = body.pose();
        // The exchange pass over the permeable texels runs on the backend (one kernel pass,
        // summed per node); the graph applies it, then moves water inside.
        bool moved = false;
        if (!f->graph.samples().empty()) {
            const ExchangeFrame frame = f->graph.exchangeFrame(pose, time_);
            if (Status s = withBackend([&](BuoyancyBackend& b) {
                    return b.evaluateExchange(f->exchangeSet, frame, scene_.water, f->rates);
                });
                !s.ok())
                return s;
            moved = f->graph.applyExchange(pose, frameTime, f->rates);
        }
        moved = f->graph.flowInside(pose.rotation, frameTime) || moved;
        changedLastFrame_[i] = moved;
        ++statistics_.graphSteps;
        // With the free surface the water's centre of mass also moves when the body turns.
        const bool turned = f->graph.settings().freeSurface && body.water > 0 &&
                            !pose.rotation.isApprox(f->composedAt, 1e-12);
        if (!moved && !turned) continue;
        f->composedAt = pose.rotation;
        replaceMass(i, f->graph.compose(f->hull, pose.rotation));
        body.boundingRadius =
            f->hullRadius + (body.mass.centerOfMass - f->hull.centerOfMass).norm();
        body.water = f->graph.storedWater();
        ++statistics_.waterCompositions;
    }
    return Ok{};
}

bool World::outOfWater(const SimulatedBody& body, const RigidBodyState& state) const {
    return state.position.y() - body.boundingRadius > scene_.water.maxHeight();
}

Status World::evaluateAll(double time, int subStep) {
    // Reused every step: no allocation once the first step has sized them.
    std::vector<BodyRequest>& requests = scratchRequests_;
    std::vector<std::size_t>& which = scratchBodies_;
    requests.clear();
    which.clear();
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        SimulatedBody& body = bodies_[i];
        if (body.asleep) continue;                     // keeps the load it fell asleep with
        if (subStep % stepStrides_[i] != 0) continue;  // keeps the load of its step
        if (outOfWater(body, body.state)) {
            body.buoyancy = BuoyancyResult{};
            body.buoyancy.centerOfBuoyancy = body.state.position;
            ++statistics_.skippedOutOfWater;
            continue;
        }
        requests.push_back(requestFor(body, body.state, time));
        which.push_back(i);
    }
    if (requests.empty()) return Ok{};
    std::vector<BuoyancyResult>& results = scratchResults_;
    results.resize(requests.size());
    if (Status s = withBackend(
            [&](BuoyancyBackend& b) { return b.evaluate(requests, scene_.water, results); });
        !s.ok())
        return s;
    for (std::size_t k = 0; k < which.size(); ++k) {
        SimulatedBody& body = bodies_[which[k]];
        body.buoyancy = results[k];
        toCenterOfMass(body, body.state, body.buoyancy);
        blendLevel(which[k], body.buoyancy);
    }
    statistics_.buoyancyEvaluations += requests.size();
    return Ok{};
}

Wrench World::wrenchOf(const SimulatedBody& body, const RigidBodyState& state,
                       const BuoyancyResult& buoyancy, double dt) const {
    // On flat water Archimedes' form: exactly vertical, where the texel sum of the pressure
    // leaves a horizontal residue of the discretisation error that makes a floating body
    // creep sideways. On waves the pressure integral, which carries their horizontal push.
    const bool flat = scene_.water.kind == WaterModel::Kind::Flat;
    Wrench w;
    w.force = body.mass.mass * scene_.simulation.gravity +
              (flat ? buoyancy.force : buoyancy.pressureForce);
    w.torque = flat ? buoyancy.torque : buoyancy.pressureTorque;
    // Dissipation (drag, and the radiation-damping stand-in in proportion to how much of the
    // body is in the fluid) may at most stop the body within one step, never reverse it: an
    // explicit step of a stiff drag (a fast, light or spinning body, a long step) would
    // otherwise overshoot and blow up.
    const double wet =
        body.volume > 0 ? std::clamp(buoyancy.submergedVolume / body.volume, 0.0, 1.0) : 0.0;
    auto limited = [dt](const Eigen::Vector3d& loss, const Eigen::Vector3d& momentum) {
        const double impulse = loss.norm() * dt;
        const double cap = momentum.norm();
        return impulse > cap && impulse > 0 ? Eigen::Vector3d(loss * (cap / impulse)) : loss;
    };
    Eigen::Vector3d loss = buoyancy.dragForce - wet * body.linearDamping * state.linearMomentum;
    if (body.verticalDamping != body.linearDamping) {
        // Along gravity its own rate (radiation damps a radiating body's heave).
        const double g = scene_.simulation.gravity.norm();
        const Eigen::Vector3d up =
            g > 0 ? Eigen::Vector3d(-scene_.simulation.gravity / g) : Eigen::Vector3d::UnitY();
        loss -=
            (wet * (body.verticalDamping - body.linearDamping) * up.dot(state.linearMomentum)) * up;
    }
    w.force += limited(loss, state.linearMomentum);
    w.torque += limited(buoyancy.dragTorque - wet * body.angularDamping * state.angularMomentum,
                        state.angularMomentum);
    const auto index = static_cast<std::size_t>(&body - bodies_.data());
    // The radiation memory is passive by construction (cummins.h): not capped either.
    if (const Radiating* r = radiatings_[index].get()) {
        w.force += r->memoryWrench.force;
        w.torque += r->memoryWrench.torque;
    }
    // An outside push and a resting contact are neither dissipation nor capped: they are what
    // the user asked for.
    for (const std::vector<ExternalForce>* forces : {&externalForces_, &contactForces_}) {
        if (index < forces->size() && (*forces)[index]) {
            const Wrench added = (*forces)[index](body, state);
            w.force += added.force;
            w.torque += added.torque;
        }
    }
    return w;
}

double World::stiffestFrequency(const SimulatedBody& body) const {
    // Hydrostatic restoring stiffness, bounded with the body's bounding sphere: heave
    // rho g (pi R^2), and roll rho g (pi R^4 / 4) about the smallest principal inertia.
    const double rhoG = body.fluid.density * body.fluid.gravity;
    const double R = body.boundingRadius;
    const double heave = rhoG * std::numbers::pi * R * R / body.mass.mass;
    const auto i = static_cast<std::size_t>(&body - bodies_.data());
    if (smallestInertia_.size() != bodies_.size()) {
        smallestInertia_.resize(
            bodies_.size(),
            {Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN()), 0.0});
    }
    std::pair<Eigen::Matrix3d, double>& cached = smallestInertia_[i];
    if (cached.first != body.mass.inertia || !(cached.second > 0)) {
        cached.first = body.mass.inertia;
        cached.second = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(body.mass.inertia)
                            .eigenvalues()
                            .minCoeff();
    }
    const double smallestInertia = cached.second;
    const double roll = rhoG * std::numbers::pi * std::pow(R, 4) / 4.0 / smallestInertia;
    return std::sqrt(std::max(heave, roll));
}

Result<int> World::stableStepsOf(const SimulatedBody& body, double frameTime) const {
    // Symplectic Euler is stable below omega dt = 2, and its energy error shrinks with
    // omega dt: enough steps that omega dt stays under simulation.maxPhaseStep for the body's
    // stiffness and for its spin (|w| dt is the angle a step turns the body through; beyond
    // about pi a step cannot tell the spin from a slower one). A body needing more than
    // kMaxSubSteps is refused: clamping its steps made a 1e-40 m body, or one spun to
    // 1e50 rad/s, run into garbage or NaN with exit 0.
    const double maxPhase = scene_.simulation.maxPhaseStep;
    const double stiffness = stiffestFrequency(body);
    const double spin = angularVelocity(body.state, body.mass).norm();
    const double needed = std::ceil(std::max(stiffness, spin) * frameTime / maxPhase);
    if (!(needed <= kMaxSubSteps)) {
        std::ostringstream m;
        m << "body '" << body.name << "': a stable step needs " << needed
          << " sub-steps a frame (hydrostatic frequency " << stiffness << " rad/s, spin " << spin
          << " rad/s, time_step " << frameTime << " s, max_phase_step " << maxPhase
          << "), more than the limit World::kMaxSubSteps = " << kMaxSubSteps << ": the body is too "
          << "small or too light for its medium (mass " << body.mass.mass << " kg, radius "
          << body.boundingRadius << " m) or spins too fast";
        return makeError(ErrorKind::invalidArgument, m.str());
    }
    return static_cast<int>(needed);
}

Result<int> World::subStepsFor(double frameTime, std::vector<int>* perBody) const {
    int most = scene_.simulation.subSteps;
    if (perBody) perBody->assign(bodies_.size(), 1);
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        if (bodies_[i].asleep) continue;  // not integrated: its stiffness asks for no step
        const Result<int> needed = stableStepsOf(bodies_[i], frameTime);
        if (!needed) return needed.error();
        if (perBody) (*perBody)[i] = *needed;
        most = std::max(most, *needed);
    }
    return most;
}

int World::stepStride(std::size_t i, int level, int subSteps) const {
    const Detail* d = details_[i].get();
    if (!d) return 1;
    return plimsoll_eval::stepStride(levelPolicy_.fewerStepsWhenCoarser, subSteps,
                                     scene_.simulation.subSteps, stableSteps_[i], level,
                                     static_cast<int>(d->levels->size()) - 1);
}

void World::chooseStepStrides(int subSteps) {
    stepStrides_.assign(bodies_.size(), 1);
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        if (details_[i] && !bodies_[i].asleep)
            stepStrides_[i] = stepStride(i, details_[i]->lod.level, subSteps);
    }
}

Status World::updateDeformingBodies(double time) {
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        Deformation* d = deformations_[i].get();
        if (!d) continue;
        const auto frame =
            static_cast<std::size_t>(std::floor(time * d->framesPerSecond)) % d->frames->size();
        if (frame == d->currentFrame) continue;
        d->currentFrame = frame;
        SimulatedBody& body = bodies_[i];
        regatherSurface(*d->pieces, (*d->frames)[frame], body.textures);
        if (Status s = recomputeMass(i); !s.ok()) return s;
    }
    return Ok{};
}

Status World::recomputeMass(std::size_t i) {
    SimulatedBody& body = bodies_[i];
    // The caps' share and the hollow are those of the body's mesh as it was baked.
    const SceneBody& baked = scene_.bodies[i];
    Result<MassProperties> props = bodyMassProperties(
        body.textures, materials_[i], shellDensityMaps_[i].get(), baked.wallShare.get(),
        baked.parts.hollow, "body '" + body.name + "'", shellThicknessMaps_[i].get());
    if (!props) return props.error();
    // Keep the body where it is in the world and its momenta as they are: the mesh or the
    // paint changed, the body did not jump.
    const Pose pose = body.pose();
    MassProperties full = *props;
    body.boundingRadius = boundingRadiusAbout(body.textures, props->centerOfMass);
    if (Flooding* f = floodings_[i].get()) {
        f->hull = *props;
        f->hullRadius = body.boundingRadius;
        full = f->graph.compose(*props, pose.rotation);
        body.boundingRadius += (full.centerOfMass - props->centerOfMass).norm();
    }
    const MassDistribution old = body.mass;
    body.mass = toDistribution(full);
    body.mass.addedMass = old.addedMass;  // the water around the body did not change
    body.mass.addedInertia = old.addedInertia;
    body.volume = props->volume;
    body.backendCenter = props->centerOfMass;
    body.state.position = pose.apply(body.mass.centerOfMass);
    ++statistics_.massRecomputations;
    return withBackend([&](BuoyancyBackend& b) -> Status {
        if (const Detail* d = details_[i].get()) {
            // Every level's entries are relative to the centre of mass, which moved.
            for (std::size_t k = 0; k < d->ids.size(); ++k) {
                if (Status s =
                        b.updateBody(d->ids[k], *(*d->levels)[k].textures, body.backendCenter);
                    !s.ok())
                    return s;
            }
            return Ok{};
        }
        return b.updateBody(body.backendId, body.textures, body.backendCenter);
    });
}

Status World::setMaterial(std::size_t i, const MaterialDesc& material,
                          std::shared_ptr<const PaintedMap> shellDensityMap,
                          std::shared_ptr<const PaintedMap> shellThicknessMap) {
    if (i >= bodies_.size()) {
        return makeError(ErrorKind::invalidArgument, "setMaterial: no body " + std::to_string(i));
    }
    materials_[i] = material;
    shellDensityMaps_[i] = std::move(shellDensityMap);
    shellThicknessMaps_[i] = std::move(shellThicknessMap);
    say("body '" + bodies_[i].name + "': material changed, mass properties recomputed");
    wakeBody(i);
    return recomputeMass(i);
}

Status World::advanceFrame() {
    const SimulationDesc& sim = scene_.simulation;
    wakeWhereNeeded();
    const Result<int> needed = subStepsFor(sim.timeStep, &stableSteps_);
    if (!needed) return needed.error();
    const int subSteps = *needed;
    if (subSteps > sim.subSteps && subSteps != reportedSubSteps_) {
        say("taking " + std::to_string(subSteps) + " sub-steps a frame instead of " +
            std::to_string(sim.subSteps) +
            ": a body's hydrostatic stiffness needs them for a "
            "stable step");
        reportedSubSteps_ = subSteps;
    }
    const double dt = sim.timeStep / subSteps;
    // The velocities at the frame's start: their change over the frame tells a body at rest
    // from one at the turning point of a swing.
    frameStartVelocities_.resize(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        const SimulatedBody& body = bodies_[i];
        frameStartVelocities_[i] = {linearVelocity(body.state, body.mass),
                                    angularVelocity(body.state, body.mass)};
    }
    if (Status s = chooseLevels(subSteps); !s.ok()) return s;
    chooseStepStrides(subSteps);
    for (int sub = 0; sub < subSteps; ++sub) {
        if (Status s = updateDeformingBodies(time_); !s.ok()) return s;
        const std::size_t skippedBefore = statistics_.skippedOutOfWater;
        if (sim.integrator == Integrator::RK4) {
            // RK4 needs the wrench at intermediate states: one evaluation per stage and body.
            // Radiation takes its share from the previous step's start (the first stage sets
            // body.buoyancy), and holds its memory force over the stages.
            for (std::size_t i = 0; i < bodies_.size(); ++i) {
                SimulatedBody& body = bodies_[i];
                if (body.asleep || sub % stepStrides_[i] != 0) continue;
                const double bodyDt = dt * stepStrides_[i];
                startRadiationStep(i, body.buoyancy.submergedVolume);
                Status failure = Ok{};
                bool firstStage = true;
                const WrenchFunction wrench = [&](const RigidBodyState& state, double t) {
                    if (outOfWater(body, state))
                        return wrenchOf(body, state, BuoyancyResult{}, bodyDt);
                    const BodyRequest request = requestFor(body, state, t);
                    BuoyancyResult result;
                    if (Status s = withBackend([&](BuoyancyBackend& b) {
                            return b.evaluate({&request, 1}, scene_.water, {&result, 1});
                        });
                        !s.ok())
                        failure = s;
                    toCenterOfMass(body, state, result);
                    blendLevel(i, result);
                    // The first stage is the state at the start of the step: what
                    // SimulatedBody::buoyancy promises (drawn and plotted by the editor).
                    if (firstStage) body.buoyancy = result;
                    firstStage = false;
                    ++statistics_.buoyancyEvaluations;
                    return wrenchOf(body, state, result, bodyDt);
                };
                body.state = step(body.state, body.mass, wrench, time_, bodyDt, sim.integrator);
                if (!failure.ok()) return failure;
                finishRadiationStep(i, bodyDt);
            }
        } else {
            // Euler integrators take the wrench at the start of the step only: one batch for
            // every body whose step starts now.
            if (Status s = evaluateAll(time_, sub); !s.ok()) return s;
            const auto stepBody = [&](std::size_t i) {
                SimulatedBody& body = bodies_[i];
                const double bodyDt = dt * stepStrides_[i];
                startRadiationStep(i, body.buoyancy.submergedVolume);
                const Wrench w = wrenchOf(body, body.state, body.buoyancy, bodyDt);
                body.state = step(
                    body.state, body.mass, [&](const RigidBodyState&, double) { return w; }, time_,
                    bodyDt, sim.integrator);
                finishRadiationStep(i, bodyDt);
            };
            // Each body's step touches only its own state: those without a caller's force
            // function are stepped on the backend's workers, the others here, so that the
            // caller's functions are only ever called on this thread. The same bits either way.
            std::vector<std::size_t>& onWorkers = scratchStepping_;
            onWorkers.clear();
            for (std::size_t i = 0; i < bodies_.size(); ++i) {
                if (bodies_[i].asleep || sub % stepStrides_[i] != 0) continue;
                if (hasForceFunction(i))
                    stepBody(i);
                else
                    onWorkers.push_back(i);
            }
            backend_->forEach(onWorkers.size(), [&](std::size_t k) { stepBody(onWorkers[k]); });
        }
        advanceBlends();
        if (statistics_.skippedOutOfWater > skippedBefore && !reportedSkip_) {
            say("a body above the highest water surface skips the buoyancy kernels "
                "(bounding-sphere test); counted in the statistics from now on");
            reportedSkip_ = true;
        }
        ++statistics_.steps;
        time_ += dt;
    }
    if (Status s = stepWaterGraphs(sim.timeStep); !s.ok()) return s;
    sleepWhereRested(sim.timeStep);
    return Ok{};
}

bool World::hasForceFunction(std::size_t i) const {
    return (i < externalForces_.size() && externalForces_[i]) ||
           (i < contactForces_.size() && contactForces_[i]);
}

bool World::pushed(std::size_t i) const {
    if (i >= externalForces_.size() || !externalForces_[i]) return false;
    const Wrench w = externalForces_[i](bodies_[i], bodies_[i].state);
    return w.force.squaredNorm() > 0 || w.torque.squaredNorm() > 0;
}

namespace {

/// The water's surface above the body's centre of mass: its height and the speed of the water
/// there, what decides whether the water is calm where the body floats.
struct SurfaceAbove {
    double height = 0, speed = 0;
};

SurfaceAbove surfaceAbove(const WaterModel& water, const Eigen::Vector3d& point, double time) {
    SurfaceAbove s;
    s.height = water.height(point.x(), point.z(), time);
    s.speed = water.velocity({point.x(), s.height, point.z()}, time).norm();
    return s;
}

}  // namespace

void World::wakeWhereNeeded() {
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        SimulatedBody& body = bodies_[i];
        if (!body.asleep) continue;
        const SurfaceAbove surface = surfaceAbove(scene_.water, body.state.position, time_);
        if (plimsoll_eval::mustWake(sleep_[i], scene_.simulation.sleep, surface.speed,
                                    surface.height, pushed(i))) {
            wakeBody(i);
        } else {
            ++statistics_.sleepingBodyFrames;
        }
    }
}

void World::sleepWhereRested(double frameTime) {
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        SimulatedBody& body = bodies_[i];
        if (body.asleep) continue;
        plimsoll_eval::RestSample sample;
        const Eigen::Vector3d v = linearVelocity(body.state, body.mass);
        const Eigen::Vector3d w = angularVelocity(body.state, body.mass);
        sample.speed = v.norm();
        sample.spin = w.norm();
        sample.acceleration = (v - frameStartVelocities_[i].linear).norm() / frameTime;
        sample.angularAcceleration = (w - frameStartVelocities_[i].angular).norm() / frameTime;
        plimsoll_eval::sampleWaterIfStill(
            scene_.simulation.sleep, sample, [&](double& height, double& speed) {
                const SurfaceAbove surface = surfaceAbove(scene_.water, body.state.position, time_);
                height = surface.height;
                speed = surface.speed;
            });
        // The outside force is the caller's function: asked only of a body otherwise at rest.
        sample.pushed =
            plimsoll_eval::stillOnCalmWater(scene_.simulation.sleep, sample) && pushed(i);
        sample.changing = changedLastFrame_[i] || body.deforms;
        if (!plimsoll_eval::countRest(sleep_[i], scene_.simulation.sleep, sample, frameTime))
            continue;
        // Asleep the body holds its pose at rest; the little its radiation memory still holds
        // after this long at rest is let go, so that it wakes without an old push.
        body.asleep = true;
        body.state.linearMomentum.setZero();
        body.state.angularMomentum.setZero();
        if (Radiating* r = radiatings_[i].get()) {
            r->memory = memoryStateFor(r->radiation->model);
            r->memoryWrench = Wrench{};
        }
        ++statistics_.fallsAsleep;
    }
}

void World::wakeBody(std::size_t i) {
    if (!bodies_[i].asleep) return;
    bodies_[i].asleep = false;
    plimsoll_eval::wake(sleep_[i]);
    ++statistics_.wakeUps;
}

Status World::wake(std::size_t i) {
    if (i >= bodies_.size()) {
        return makeError(ErrorKind::invalidArgument, "wake: no body " + std::to_string(i));
    }
    wakeBody(i);
    return Ok{};
}

Status World::setForceOf(std::vector<ExternalForce>& forces, std::size_t i, ExternalForce force,
                         const char* what) {
    if (i >= bodies_.size()) {
        return makeError(ErrorKind::invalidArgument,
                         std::string(what) + ": no body " + std::to_string(i));
    }
    forces.resize(bodies_.size());
    forces[i] = std::move(force);
    wakeBody(i);
    return Ok{};
}

Status World::setExternalForce(std::size_t i, ExternalForce force) {
    return setForceOf(externalForces_, i, std::move(force), "setExternalForce");
}

Status World::setContactForce(std::size_t i, ExternalForce contact) {
    return setForceOf(contactForces_, i, std::move(contact), "setContactForce");
}

void World::setWater(const WaterModel& water) {
    scene_.water = water;
    scene_.water.gravity = scene_.simulation.gravity.norm();  // the scene's one gravity
    for (std::size_t i = 0; i < bodies_.size(); ++i) wakeBody(i);
}

void World::setIntegrator(Integrator integrator) { scene_.simulation.integrator = integrator; }

Status World::setBodyState(std::size_t i, const RigidBodyState& state) {
    if (i >= bodies_.size()) {
        return makeError(ErrorKind::invalidArgument, "setBodyState: no body " + std::to_string(i));
    }
    bodies_[i].state = state;
    wakeBody(i);
    return Ok{};
}

Status World::setLevelPolicy(const LevelPolicy& policy) {
    const auto refuse = [](const std::string& what) {
        return makeError(ErrorKind::invalidArgument, "setLevelPolicy: " + what);
    };
    if (!policy.pointOfInterest.allFinite()) return refuse("the point of interest is not finite");
    if (!(policy.nearDistance > 0) || !std::isfinite(policy.nearDistance))
        return refuse("nearDistance must be a positive distance (m)");
    if (!(policy.margin >= 0) || !std::isfinite(policy.margin))
        return refuse("margin must be 0 or more");
    if (!(policy.budgetUs >= 0)) return refuse("budgetUs must be 0 or more");
    if (policy.holdFrames < 0) return refuse("holdFrames must be 0 or more");
    if (policy.blendFrames < 1) return refuse("blendFrames must be at least 1");
    for (double importance : policy.importance) {
        if (!(importance >= 0) || !(importance <= 1))
            return refuse("an importance is outside 0..1");
    }
    levelPolicy_ = policy;
    return Ok{};
}

const std::vector<BuoyancyLevel>* World::levels(std::size_t body) const {
    return body < details_.size() && details_[body] ? details_[body]->levels.get() : nullptr;
}

int World::targetLevel(std::size_t i, const Detail& d, const std::vector<int>& budgetLevels) const {
    const LevelPolicy& p = levelPolicy_;
    const int finest = static_cast<int>(d.levels->size()) - 1;
    switch (p.kind) {
        case LevelPolicy::Kind::finest:
            return finest;
        case LevelPolicy::Kind::distance:
            return plimsoll_eval::levelAtDistance(
                (bodies_[i].state.position - p.pointOfInterest).norm(), p.nearDistance, p.margin,
                d.lod.level, finest);
        case LevelPolicy::Kind::importance:
            return plimsoll_eval::levelOfImportance(i < p.importance.size() ? p.importance[i] : 1.0,
                                                    p.nearDistance, p.margin, d.lod.level, finest);
        case LevelPolicy::Kind::budget:
            return budgetLevels[i];
    }
    return finest;
}

Status World::chooseLevels(int subSteps) {
    if (std::none_of(details_.begin(), details_.end(), [](const auto& d) { return d != nullptr; }))
        return Ok{};
    const LevelPolicy& p = levelPolicy_;
    // The budget's greedy pass (plimsoll_eval::budgetLevels). A sleeping body costs nothing.
    std::vector<int> budgetLevels;
    if (p.kind == LevelPolicy::Kind::budget) {
        std::vector<std::vector<double>> costs(bodies_.size());
        std::vector<plimsoll_eval::BudgetEntry> entries(bodies_.size());
        for (std::size_t i = 0; i < bodies_.size(); ++i) {
            const Detail* d = details_[i].get();
            if (!d || bodies_[i].asleep) continue;
            // A level's cost a frame: its cost per evaluation times the steps it takes.
            for (std::size_t k = 0; k < d->levels->size(); ++k) {
                const int steps = subSteps / stepStride(i, static_cast<int>(k), subSteps);
                costs[i].push_back((*d->levels)[k].evaluationUs * steps);
            }
            entries[i] = {(bodies_[i].state.position - p.pointOfInterest).norm(), costs[i].data(),
                          costs[i].size()};
        }
        plimsoll_eval::budgetLevels(entries, 1.0, p.budgetUs, budgetLevels);
    }
    struct Switch {
        std::size_t body;
        int from = 0;            ///< the level it leaves
        BuoyancyResult carried;  ///< what is left of a blend still running
    };
    std::vector<Switch> switching;
    std::vector<BodyRequest> requests;
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        Detail* d = details_[i].get();
        if (!d) continue;
        SimulatedBody& body = bodies_[i];
        // Asleep it keeps the load it fell asleep with, of the level it had.
        if (!d->lod.countFrame(p.holdFrames) || body.asleep) continue;
        const int target = targetLevel(i, *d, budgetLevels);
        if (target == d->lod.level) continue;
        const int from = d->lod.level;
        const double carried = d->lod.switchTo(target);
        body.backendId = d->ids[static_cast<std::size_t>(target)];
        body.levelSize = (*d->levels)[static_cast<std::size_t>(target)].size;
        ++statistics_.levelSwitches;
        if (outOfWater(body, body.state)) continue;  // no water, no force to blend
        // Both levels at the same state: their difference is faded out from here.
        Switch sw{i, from, BuoyancyResult{}};
        sw.carried.centerOfBuoyancy.setZero();
        if (carried > 0) addScaled(sw.carried, d->offset, carried);
        requests.push_back(requestFor(body, body.state, time_));  // its id set below
        requests.push_back(requestFor(body, body.state, time_));
        switching.push_back(sw);
    }
    if (requests.empty()) return Ok{};
    std::vector<BuoyancyResult> results(requests.size());
    if (Status s = withBackend([&](BuoyancyBackend& b) {
            // The ids now (withBackend may have moved the bodies to the reference backend).
            for (std::size_t k = 0; k < switching.size(); ++k) {
                const Detail& d = *details_[switching[k].body];
                requests[2 * k].body = d.ids[static_cast<std::size_t>(switching[k].from)];
                requests[2 * k + 1].body = d.ids[static_cast<std::size_t>(d.lod.level)];
            }
            return b.evaluate(requests, scene_.water, results);
        });
        !s.ok())
        return s;
    statistics_.buoyancyEvaluations += requests.size();
    for (std::size_t k = 0; k < switching.size(); ++k) {
        Detail& d = *details_[switching[k].body];
        d.offset = switching[k].carried;
        addScaled(d.offset, results[2 * k], 1.0);
        addScaled(d.offset, results[2 * k + 1], -1.0);
        d.lod.startBlend(p.blendFrames, subSteps);
    }
    return Ok{};
}

void World::blendLevel(std::size_t i, BuoyancyResult& result) const {
    const Detail* d = details_[i].get();
    if (!d || d->lod.weight() <= 0) return;
    addScaled(result, d->offset, d->lod.weight());
}

void World::advanceBlends() {
    for (const std::unique_ptr<Detail>& d : details_) {
        if (d) d->lod.advance();
    }
}

double World::mechanicalEnergy(std::size_t i) const {
    const SimulatedBody& body = bodies_[i];
    const double g = scene_.simulation.gravity.norm();
    double energy =
        kineticEnergy(body.state, body.mass) + body.mass.mass * g * body.state.position.y();
    if (scene_.water.kind == WaterModel::Kind::Flat && !outOfWater(body, body.state)) {
        BodyFrame frame;
        frame.pose = body.pose();
        frame.centerOfMass = body.mass.centerOfMass;
        const BuoyancyResult r =
            evaluateBuoyancyReference(body.textures, frame, scene_.water, body.fluid);
        energy += body.fluid.density * g * r.submergedVolume *
                  (scene_.water.level - r.centerOfBuoyancy.y());
    }
    if (const Radiating* r = radiatings_[i].get())
        energy += memoryEnergy(r->radiation->model, r->memory);
    return energy;
}

}  // namespace plimsoll
