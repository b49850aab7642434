// World: the bodies of a scene stepped through time — gravity, buoyancy and drag from a
// compute backend (all bodies in one batch per step where the integrator allows it), then the
// rigid-body integrator (docs/design.md, "Rigid body"). World reads no files: it takes a Scene
// (scene.h) whose bodies already hold their meshes, textures, mass properties, water graphs and
// painted maps. Only what a scene needs is computed:
//  - a rigid body with constant material keeps the mass properties its scene body brought;
//  - a deforming body regathers its textures and recomputes its mass properties on the
//    frames its mesh changes;
//  - a body whose bounding sphere lies above the highest water surface skips the kernels;
//  - a body with a water graph (BodyDesc::waterGraph) steps it once a frame, after the
//    frame's integration steps, and composes the water's mass properties with its own when
//    water moved (or, with the free-surface model, when the body turned); a body without one
//    computes no graph at all;
//  - a body with radiation (BodyDesc::radiates, SceneBody::radiation) carries its added mass in
//    its mass matrix and integrates the radiation memory with it (Cummins' equation,
//    docs/radiation.md); a body without it runs exactly as it would without the feature;
//  - a body with a level ladder (SceneBody::levels) is evaluated at the level the caller's
//    policy picks (setLevelPolicy: the finest unless told otherwise), switching with
//    hysteresis and blending the old level's force into the new one's, so that it never kicks;
//  - a body at rest on calm water falls asleep (simulation.sleep, plimsoll_eval/sleep.hpp):
//    no evaluation, no integration, no graph step, one look at the water above it a frame,
//    until the water, an outside force or a call that changes it wakes it.
// The log callback is told what was skipped and why.
#pragma once

#include "plimsoll/bake/bake.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/compute/compute.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/scene/scene_desc.h"
#include "plimsoll/scene/scene.h"
#include "plimsoll/core/result.h"
#include "plimsoll/physics/rigid_body.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace plimsoll {

/// A body as the simulation holds it.
struct SimulatedBody {
    std::string name;
    MassDistribution mass;  ///< current (changes for deforming bodies)
    double volume = 0;      ///< enclosed volume, m^3 (texture)
    RigidBodyState state;
    SurfaceTextures textures;   ///< current surface samples, object space
    double boundingRadius = 0;  ///< about the centre of mass, m
    FluidSettings fluid;
    double linearDamping = 0;    ///< 1/s, at full submersion, horizontal (BodyDesc)
    double verticalDamping = 0;  ///< 1/s, the same along gravity
    double angularDamping = 0;   ///< 1/s
    BuoyancyResult buoyancy;     ///< at the start of the last step
    std::size_t backendId = 0;
    /// The object-space point the backend's entries are relative to: the centre of mass of
    /// the body without its water (= mass.centerOfMass for a body without a water graph).
    Eigen::Vector3d backendCenter = Eigen::Vector3d::Zero();
    bool deforms = false;
    double water = 0;     ///< m^3 in the water graph now (0 without one)
    bool asleep = false;  ///< at rest on calm water: not computed (world.h)
    /// Texels per side of the level its buoyancy is evaluated at now (the texture size for a
    /// body without a level ladder).
    int levelSize = 0;

    /// Object -> world placement now.
    Pose pose() const { return poseOf(state, mass); }
};

/// A force from outside the simulation on one body (a user's mouse grab, a thruster): called at
/// every integration step (every RK4 stage) with the body and its state there, it returns the
/// wrench about the body's centre of mass, world axes (N, N m). Added to gravity, buoyancy and
/// drag before the integrator uses them.
using ExternalForce = std::function<Wrench(const SimulatedBody& body, const RigidBodyState& state)>;

/// How the World picks the level of each body with a level ladder (SceneBody::levels) every
/// frame (docs/design.md, "Level of detail"). Whatever the policy, a body switches at most once
/// every holdFrames frames, not while asleep, and its force and torque go from the old level's
/// to the new one's over blendFrames frames (both levels evaluated at the switch; their
/// difference is faded out linearly step by step), so a switch changes the acceleration by at
/// most the two levels' difference over blendFrames x sub-steps per step.
struct LevelPolicy {
    enum class Kind {
        finest,      ///< every body at its finest level (texture_size): the default
        distance,    ///< by distance from pointOfInterest
        importance,  ///< by importance[i]: 1 is the finest, each halving one level coarser
        budget,      ///< within budgetUs a frame: the bodies nearest pointOfInterest first
    };
    Kind kind = Kind::finest;
    Eigen::Vector3d pointOfInterest = Eigen::Vector3d::Zero();  ///< world, m (a camera)
    /// m: the finest level within it of the point of interest, one level coarser each time the
    /// distance doubles (distance policy: nearDistance 2^k takes the k-th level down).
    double nearDistance = 50.0;
    /// Hysteresis: a body changes level only when its distance (or nearDistance / importance)
    /// is beyond a boundary by this fraction of it (0.15: 15%).
    double margin = 0.15;
    /// Per body (index as in bodies()), in 0..1: 1 the finest level, each halving one level
    /// coarser (it acts as the distance nearDistance / (importance sqrt 2), the middle of its
    /// band), 0 the coarsest. Missing entries count as 1.
    std::vector<double> importance;
    /// Microseconds a frame for every body with a ladder, summing each level's measured cost
    /// per evaluation (BuoyancyLevel::evaluationUs, one thread) times the steps it takes a
    /// frame at that level (fewerStepsWhenCoarser): every body
    /// starts at its coarsest level, then the bodies nearest pointOfInterest take the finest
    /// level the rest of the budget pays for, one after the other (greedy).
    double budgetUs = 0;
    int holdFrames = 30;  ///< at least this many frames between two switches of a body
    int blendFrames = 8;  ///< frames over which a switch's force is blended, >= 1
    /// Temporal level of detail: a body takes the project's sub-steps at its finest level and
    /// half as many at each coarser one, never fewer than a stable step needs
    /// (plimsoll_eval::stepsAtLevel). False: every body takes every sub-step.
    bool fewerStepsWhenCoarser = true;
};

/// Counters of what the world did and did not compute (for logs, tests and the editor).
struct WorldStatistics {
    std::size_t steps = 0;                ///< integration steps (sub-steps)
    std::size_t buoyancyEvaluations = 0;  ///< body evaluations sent to the backend
    std::size_t skippedOutOfWater = 0;    ///< body-steps skipped by the bounding-sphere test
    std::size_t massRecomputations = 0;   ///< mass properties computed after creation
    std::size_t graphSteps = 0;           ///< water-graph steps (body-frames)
    std::size_t waterCompositions = 0;    ///< body + water mass properties composed again
    std::size_t sleepingBodyFrames = 0;   ///< body-frames a body slept through
    std::size_t fallsAsleep = 0;          ///< times a body fell asleep
    std::size_t wakeUps = 0;              ///< times a sleeping body woke
    std::size_t levelSwitches = 0;        ///< times a body changed its level of detail
};

class World {
public:
    /// At most this many integration steps a frame. A body whose stiffness or spin needs more
    /// for a stable step (a 1e-40 m body, a spin of 1e50 rad/s) is refused, not stepped too
    /// coarsely into garbage.
    static constexpr int kMaxSubSteps = 20000;

    /// Registers every body of `scene` with `backend` (the scene's bodies are shared, not
    /// copied). Refuses a gravity checkGravity refuses and a water graph it cannot step, naming
    /// the body.
    static Result<std::unique_ptr<World>> create(Scene scene,
                                                 std::unique_ptr<BuoyancyBackend> backend,
                                                 LogFunction log = {});

    ~World();

    /// Advances one frame: simulation.subSteps integration steps, or more where a body's
    /// hydrostatic stiffness needs them (a 1 mm body, a long time step): the log says so.
    Status advanceFrame();

    /// Changes a body's material (a repainted density or thickness map, a new density): its
    /// mass properties are recomputed now, once, keeping its centre of mass's place and
    /// momenta. `shellDensityMap` is the painted shell density and `shellThicknessMap` the
    /// painted relative shell thickness (null: uniform).
    Status setMaterial(std::size_t body, const MaterialDesc& material,
                       std::shared_ptr<const PaintedMap> shellDensityMap = nullptr,
                       std::shared_ptr<const PaintedMap> shellThicknessMap = nullptr);

    /// Body i's external force (world.h ExternalForce); an empty function removes it. The body
    /// wakes, and stays awake while the force is not zero.
    Status setExternalForce(std::size_t body, ExternalForce force);

    /// Body i's resting contact (a sea floor it lies on): added to its forces as the external
    /// force is, but never a push. A body at rest on it (every speed and acceleration under
    /// the sleep thresholds, calm water, no water moving in its graph) falls asleep although
    /// the contact holds it up, and asleep it is not asked; the water, an external force, a
    /// wake() or a new state wakes it. An empty function removes it. The body wakes.
    Status setContactForce(std::size_t body, ExternalForce contact);

    /// Replaces the medium's surface (level, waves) from the next step on: an editor changes
    /// the water while the simulation runs. Every sleeping body wakes.
    void setWater(const WaterModel& water);

    /// Wakes body i if it sleeps (a game's or an editor's own reason: a collision, a drag).
    Status wake(std::size_t body);

    /// How bodies with a level ladder pick their level, from the next frame on (world.h
    /// LevelPolicy). Refuses a non-finite point, a nearDistance or margin that is not positive
    /// (margin may be 0), a budget below 0, holdFrames below 0 or blendFrames below 1.
    Status setLevelPolicy(const LevelPolicy& policy);
    const LevelPolicy& levelPolicy() const { return levelPolicy_; }

    /// Body i's ladder (coarsest first), or null for a body with one level.
    const std::vector<BuoyancyLevel>* levels(std::size_t body) const;

    /// Changes the integrator from the next step on.
    void setIntegrator(Integrator integrator);

    /// Puts body i in `state` (its centre of mass's place, orientation and momenta): a reset,
    /// or a state carried over from another world of the same scene. The body wakes.
    Status setBodyState(std::size_t body, const RigidBodyState& state);

    /// Sets the simulated time (s; waves and deforming bodies follow it): a world rebuilt
    /// from the same scene carries on where the previous one was.
    void setTime(double time) { time_ = time; }

    /// Body i's radiation, or null for a body without.
    const BodyRadiation* radiation(std::size_t body) const;

    /// Body i's water graph, or null for a sealed body.
    const WaterGraphSimulation* waterGraph(std::size_t body) const;

    double time() const { return time_; }
    const std::vector<SimulatedBody>& bodies() const { return bodies_; }
    const WorldStatistics& statistics() const { return statistics_; }
    /// The scene as it runs now (water and integrator as last set).
    const Scene& scene() const { return scene_; }
    const BuoyancyBackend& backend() const { return *backend_; }

    /// Kinetic + gravitational potential energy of body i plus, on flat water, the
    /// hydrostatic potential rho_f g V_s (h - y_B) of its displaced water (J). Conserved by
    /// the exact dynamics without drag: the stability tests watch it. With radiation, plus the
    /// energy held in the radiation memory (body and water together never gain energy).
    double mechanicalEnergy(std::size_t body) const;

private:
    /// Sets body i's entry of `forces` (external or contact) and wakes it; `what` names the call.
    Status setForceOf(std::vector<ExternalForce>& forces, std::size_t i, ExternalForce force,
                      const char* what);
    World(Scene scene, std::unique_ptr<BuoyancyBackend> backend, LogFunction log);

    struct Deformation;  // frames and piece table of a deforming body
    struct Flooding;     // water graph of a hollow or permeable body
    struct Radiating;    // radiation model and memory state of a body with radiation
    struct Detail;       // level ladder of a body: backend ids, level in use, blend
    /// Picks every laddered body's level for this frame (levelPolicy_), evaluates both levels
    /// of each body that switches and starts its blend.
    Status chooseLevels(int subSteps);
    /// The target level index of laddered body i under the policy (before the hold rule).
    int targetLevel(std::size_t i, const Detail& d, const std::vector<int>& budgetLevels) const;
    /// Adds body i's remaining blend (old level minus new, faded) to `result`.
    void blendLevel(std::size_t i, BuoyancyResult& result) const;
    /// One sub-step of every blend has passed.
    void advanceBlends();
    /// Before body i's step: its entrained share, added mass and memory wrench from
    /// `submergedVolume` (m^3); nothing for a body without radiation.
    void startRadiationStep(std::size_t i, double submergedVolume);
    /// After body i's step: the memory advanced by dt with the body's new velocity.
    void finishRadiationStep(std::size_t i, double dt);
    /// The backend request for `body` in `state`, and the result's torques moved from the
    /// backend's centre to the body's centre of mass (they differ when the body holds water).
    BodyRequest requestFor(const SimulatedBody& body, const RigidBodyState& state,
                           double time) const;
    void toCenterOfMass(const SimulatedBody& body, const RigidBodyState& state,
                        BuoyancyResult& result) const;
    Result<std::unique_ptr<Flooding>> makeFlooding(const SceneBody& body) const;
    /// Steps every water graph by one frame and recomposes the mass where water moved.
    Status stepWaterGraphs(double frameTime);
    /// Sets body i's mass to `mass`, keeping its pose and its velocities.
    void replaceMass(std::size_t i, const MassProperties& mass);
    Status addBody(const SceneBody& desc);
    /// Evaluates every awake body in the water whose step falls on sub-step `subStep`
    /// (stepStrides_) in one backend batch.
    Status evaluateAll(double time, int subStep);
    /// Sub-steps of a frame of `subSteps` each step of body i spans at `level`.
    int stepStride(std::size_t i, int level, int subSteps) const;
    /// Sets stepStrides_ from each body's level this frame.
    void chooseStepStrides(int subSteps);
    Wrench wrenchOf(const SimulatedBody& body, const RigidBodyState& state,
                    const BuoyancyResult& buoyancy, double dt) const;
    /// Upper bound of the body's hydrostatic natural frequency (rad/s).
    double stiffestFrequency(const SimulatedBody& body) const;
    /// Steps a frame `body` needs for a stable step on its own; an error naming the body when
    /// that is more than kMaxSubSteps.
    Result<int> stableStepsOf(const SimulatedBody& body, double frameTime) const;
    /// Sub-steps a frame needs for a stable step of every body (and at least the project's);
    /// each awake body's own stableStepsOf into `perBody` where given.
    Result<int> subStepsFor(double frameTime, std::vector<int>* perBody = nullptr) const;
    Status updateDeformingBodies(double time);
    /// Recomputes body i's mass properties from its current textures and material.
    Status recomputeMass(std::size_t i);
    /// The bounding-sphere test: the body in `state` lies above the highest water surface.
    bool outOfWater(const SimulatedBody& body, const RigidBodyState& state) const;
    /// The outside force on body i in its state is not zero.
    bool pushed(std::size_t i) const;
    /// Body i has a caller's force function (an outside force or a resting contact).
    bool hasForceFunction(std::size_t i) const;
    /// Wakes the sleeping bodies the water or a force wakes, before a frame.
    void wakeWhereNeeded();
    /// Counts each awake body's rest after a frame; puts those that rested long enough to sleep.
    void sleepWhereRested(double frameTime);
    void wakeBody(std::size_t i);
    void say(const std::string& line) const;
    /// Runs `call` on the backend. Where an OpenCL backend fails (out of resources, a lost
    /// device), says so once on the log, moves every body to the C++ reference backend and
    /// runs `call` again there: the run goes on, slower, with the reference's results.
    Status withBackend(const std::function<Status(BuoyancyBackend&)>& call);

    Scene scene_;
    std::unique_ptr<BuoyancyBackend> backend_;
    bool fellBack_ = false;  ///< withBackend replaced a failed OpenCL backend
    LogFunction log_;
    std::vector<SimulatedBody> bodies_;
    std::vector<std::unique_ptr<Deformation>> deformations_;  ///< per body, null if rigid
    std::vector<std::unique_ptr<Flooding>> floodings_;        ///< per body, null if sealed
    std::vector<std::unique_ptr<Radiating>> radiatings_;      ///< per body, null without radiation
    std::vector<std::unique_ptr<Detail>> details_;            ///< per body, null: one level
    LevelPolicy levelPolicy_;
    std::vector<MaterialDesc> materials_;
    std::vector<std::shared_ptr<const PaintedMap>> shellDensityMaps_;  ///< per body, null: uniform
    std::vector<ExternalForce> externalForces_;                        ///< per body, empty if none
    std::vector<plimsoll_eval::SleepState> sleep_;                     ///< per body
    /// Per body: the painted shell thickness (null: uniform), the resting contact (empty: none).
    std::vector<std::shared_ptr<const PaintedMap>> shellThicknessMaps_;
    std::vector<ExternalForce> contactForces_;
    std::vector<char> changedLastFrame_;        ///< per body: its graph moved water, or it deforms
    std::vector<Motion> frameStartVelocities_;  ///< per body, at the start of the frame
    /// Per body: the sub-steps of this frame each of its steps spans (1: every sub-step), and
    /// the steps a frame its stable step needs (subStepsFor, this frame).
    std::vector<int> stepStrides_, stableSteps_;
    /// Per body: the inertia tensor whose smallest eigenvalue stiffestFrequency last took, and
    /// that eigenvalue (the mass changes only with water or material).
    mutable std::vector<std::pair<Eigen::Matrix3d, double>> smallestInertia_;
    WorldStatistics statistics_;
    double time_ = 0;
    bool reportedSkip_ = false;
    int reportedSubSteps_ = 0;
    std::vector<BodyRequest> scratchRequests_;  ///< evaluateAll's per-step lists
    std::vector<std::size_t> scratchBodies_;
    std::vector<std::size_t> scratchStepping_;  ///< the bodies a sub-step integrates on workers
    std::vector<BuoyancyResult> scratchResults_;
};

}  // namespace plimsoll
