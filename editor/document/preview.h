// The editor's live preview: a simulation session over a World built from the document's
// scene in memory (Document::simulationScene: every body, unsaved edits included). No GL and no
// ImGui here: the panels drive it and the tests run it headless.
//  - play / pause / single step / reset, and a time scale; update() turns wall-clock time into
//    whole frames of simulation.timeStep through an accumulator whose catch-up is
//    capped, so a slow frame never freezes the UI in a spiral of ever more steps;
//  - the water model and the integrator change while it runs; a new physics texture size is
//    baked on a worker thread (below the UI's priority, with progress and Cancel) and swapped
//    in (states and time carried over) when it is ready, playing or paused: no frame waits;
//  - a body can be grabbed: a spring from a point on the body to a target (the mouse ray),
//    applied as World's external force;
//  - a history of per-body quantities over time for the plots, exportable as CSV;
//  - the submerged-volume error against the exact clip at the current pose, by the function
//    `plimsoll buoyancy --compare-exact` uses (volume_check.h).
#pragma once

#include "document/sea_floor.h"

#include "plimsoll/project/project.h"
#include "plimsoll/scene/scene.h"
#include "plimsoll/core/result.h"
#include "plimsoll/physics/volume_check.h"
#include "plimsoll/scene/world.h"

#include <Eigen/Core>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll::editor {

class Document;

/// The grab spring: F = k (target - p) - c v_p at the grabbed point p (world), torque
/// (p - c.o.m.) x F. Returned as a wrench about the centre of mass.
Wrench springWrench(const SimulatedBody& body, const RigidBodyState& state,
                    const Eigen::Vector3d& objectPoint, const Eigen::Vector3d& target,
                    double stiffness, double damping);

/// The floor's contact on a body: a penalty contact on the body's points below `floorY`
/// (`objectPoints`, object space: the hull's vertices). The push is the stiffness times the
/// deepest point's depth, shared among the points below in proportion to their depths (a body
/// touching with one corner is pushed there and turns onto its side), less a damping of each
/// point's sinking speed, never a pull; along the floor each point's sliding is damped, up to
/// `friction` times its push (Coulomb). The stiffness is the body's mass times (2 pi 4 Hz)^2
/// (a resting body sinks into the floor its weight over that: at most 1.6 cm), the damping
/// critical for it. Returned about the centre of mass; zero when no point is below.
Wrench floorContactWrench(const SimulatedBody& body, const RigidBodyState& state,
                          const std::vector<Eigen::Vector3d>& objectPoints, double floorY,
                          double friction);

/// Heel and trim of an orientation, degrees: heel is the object z axis's rise (rotation about
/// the object x axis, starboard = +z down positive), trim the object x axis's rise (bow = +x up
/// positive).
Eigen::Vector2d heelAndTrimDegrees(const Eigen::Matrix3d& rotation);

/// Rotation -> degrees (rx, ry, rz) with R = Rz Ry Rx, as the project and the CLI take them.
Eigen::Vector3d eulerDegrees(const Eigen::Matrix3d& rotation);

/// One quantity over time: a column of a plot.
struct PlotSeries {
    std::string name;  ///< "buoy submerged volume"
    std::string unit;  ///< "m^3"
    std::vector<double> values;
};

/// The quantities recorded each frame, one row per simulated frame; `time` is the simulated
/// time (s). A world computes its forces while it steps, so the first row is the first frame's:
/// a row before it would show a submerged volume and buoyancy of zero that no step computed.
struct PreviewHistory {
    std::vector<double> time;
    std::vector<PlotSeries> series;
    /// Rows kept (oldest dropped first): 10 minutes at 60 frames a second.
    std::size_t capacity = 36000;
    const PlotSeries* find(const std::string& name) const;
};

/// Writes `time` and the named series (all when empty) as CSV ("time (s),NAME (UNIT),...")
/// atomically. Unknown names are an error.
Status writeHistoryCsv(const PreviewHistory& history, const std::vector<std::string>& names,
                       const std::filesystem::path& path);

struct PreviewTimings {
    double frameMs = 0;        ///< wall clock of the last frame's advanceFrame
    double kernelMs = 0;       ///< backend kernel time of the last frame (all its sub-steps)
    int subSteps = 0;          ///< integration steps of the last frame
    int framesLastUpdate = 0;  ///< frames the last update() took
    int droppedFrames = 0;     ///< frames dropped by the catch-up cap since the start
};

class PreviewSession {
public:
    /// Longest catch-up of one update(): more owed time than this is dropped (the preview
    /// runs slower than real time instead of freezing).
    static constexpr int kMaxCatchUpFrames = 4;
    /// Wall-clock milliseconds one update() may spend stepping after its first frame (the
    /// rest of the owed time is dropped too): the UI keeps its frame rate on a slow device.
    static constexpr double kUpdateBudgetMs = 25.0;

    /// Builds the World of `scene` (its bodies baked already) on this thread. `device` as
    /// createBuoyancyBackend takes it ("reference", "cpu", "gpu", an index, or empty for the
    /// default).
    static Result<std::unique_ptr<PreviewSession>> create(Scene scene, const std::string& device);
    ~PreviewSession();

    void play() { playing_ = true; }
    void pause() { playing_ = false; }
    bool playing() const { return playing_; }
    /// One frame now, playing or paused.
    Status step();
    /// Back to the scene's starting states at time 0; keeps the settings changed since
    /// (water, integrator, texture size), clears the history and releases a grab.
    Status reset();
    /// Simulated seconds per wall-clock second (0.01 .. 10).
    void setTimeScale(double scale);
    double timeScale() const { return timeScale_; }
    /// The wall-clock budget of one update() (kUpdateBudgetMs unless set; infinity lets the
    /// frame count depend on the owed time alone, as the tests that count frames need).
    void setUpdateBudgetMs(double milliseconds) { updateBudgetMs_ = milliseconds; }
    /// Advances by `wallSeconds` of wall-clock time times the time scale, in whole frames,
    /// at most kMaxCatchUpFrames and within the update budget; nothing while paused. Swaps in a
    /// finished rebuild first, paused or not. Returns the frames taken.
    Result<int> update(double wallSeconds);

    void setWater(const WaterModel& water);
    void setIntegrator(Integrator integrator);
    /// Rebakes every body at `size` texels a side on a worker thread; update() and step()
    /// swap the new world in when it is done, and until then the current one keeps running.
    /// A second request cancels a pending one without waiting for it. Returns at once.
    /// With `onlyBody`, that body alone is rebaked (the inspector's per-body size).
    void requestTextureSize(int size, std::optional<std::size_t> onlyBody = std::nullopt);
    bool rebuilding() const { return pending_ != nullptr; }
    /// The size being baked (0: none) and how far its bake is, 0..1.
    int rebuildingSize() const;
    double rebuildProgress() const;
    /// Stops the pending rebuild (its bake stops within a band of rows); the current size stays.
    void cancelRebuild();
    /// Swaps a finished rebuild in; returns at once while it runs. A failed one is dropped and
    /// its message kept in rebuildError() (the current world keeps running).
    void pollRebuild();
    /// Waits for a pending rebuild and swaps it in (tests): its error, if it failed.
    Status finishRebuild();
    /// Why the last rebuild failed ("" when it did not).
    const std::string& rebuildError() const { return rebuildError_; }
    /// The texture size the running bodies have (of body 0).
    int textureSize() const;

    /// The sea floor from the next step on (a body already below it is pushed up).
    void setSeaFloor(const SeaFloor& floor);
    const SeaFloor& seaFloor() const { return seaFloor_; }
    /// The floor's height, world y (nothing when it is off).
    std::optional<double> floorHeight() const;
    /// Body i's lowest point now, world y (its hull's lowest vertex).
    double lowestPoint(std::size_t body) const;

    /// Body i's material and painted maps (over the scene's own UVs) from the next step on,
    /// while it runs: the material and the shell density and thickness maps at once
    /// (World::setMaterial: the mass properties recomputed, the centre of mass's place and the
    /// momenta kept); a changed permeability map rebuilds the world from the scene, its baked
    /// textures kept (no bake), carrying every body's state, the time and the water in each
    /// graph, so water seeps through the new texels from the next frame.
    Status setBodyPaint(std::size_t body, const MaterialDesc& material,
                        std::shared_ptr<const PaintedMap> permeability,
                        std::shared_ptr<const PaintedMap> shellDensity,
                        std::shared_ptr<const PaintedMap> shellThickness = nullptr);
    /// Body i's water graph from the next step on, while it runs: `after` is the document's
    /// graph as edited (none: the body has no graph), `before` the document's graph the
    /// running one was made from, `settings` the body's water-graph settings. The world is
    /// rebuilt from the scene, its baked textures kept (no bake), carrying every body's state
    /// and the time. Every node keeps the water it holds now (within its new capacity) unless
    /// the edit set its water; a new node starts with its own; the nodes the scene added to
    /// the document's (the spaces behind an open hull's caps) stay; the other bodies' graphs
    /// keep their water. Reset starts from the edited graph.
    /// A graph the World cannot run (validateGraph's errors: a pipe naming a missing node, no
    /// nodes, ...) is not taken: the error names the body and the problems, the running graph
    /// stays, and graphProblem(body) says why until a valid graph is taken.
    Status setBodyGraph(std::size_t body, const std::optional<WaterGraph>& before,
                        const std::optional<WaterGraph>& after,
                        const std::optional<WaterGraphDesc>& settings);
    /// Why body i's edited water graph is not the one simulated ("pipe ... names a node that
    /// does not exist"), or empty when the edited graph runs.
    std::string graphProblem(std::size_t body) const {
        return body < graphProblems_.size() ? graphProblems_[body] : std::string();
    }
    /// Takes the document's edits of the bodies' materials, permeability, density and
    /// thickness maps and water graphs (nodes, pipes, their settings) since the last call (the
    /// first call only notes them: the preview started from them) through setBodyPaint and
    /// setBodyGraph; returns the bodies changed. A body whose maps the scene moved onto a repaired
    /// solid (its maps are not the document's pixels) keeps its paint as it is, and is named in the
    /// error: a restart of the preview takes its new paint. A graph setBodyGraph holds back is
    /// named in the error too (the other edits are taken), and tried again at the next call.
    Result<std::vector<std::size_t>> followDocument(const Document& document);

    /// Grabs body `body` at `objectPoint` (object space) and pulls it toward `target` (world)
    /// with a spring of `stiffness` (N/m; <= 0: the body's mass times (2 pi 1.5 Hz)^2) and
    /// critical damping for that stiffness.
    Status grab(std::size_t body, const Eigen::Vector3d& objectPoint, const Eigen::Vector3d& target,
                double stiffness = 0);
    void moveGrab(const Eigen::Vector3d& target) { grabTarget_ = target; }
    void release();
    bool grabbing() const { return grabbedBody_.has_value(); }
    std::optional<std::size_t> grabbedBody() const { return grabbedBody_; }
    const Eigen::Vector3d& grabTarget() const { return grabTarget_; }
    /// The grabbed point now, world (valid while grabbing).
    Eigen::Vector3d grabPoint() const;
    /// Impulse the spring has given the grabbed body since the grab, N s (for tests).
    const Eigen::Vector3d& grabImpulse() const { return grabImpulse_; }

    /// Body i's submerged volume, texture against exact, at its pose now in flat water at the
    /// scene's mean level (volume_check.h; the same device kind as the simulation).
    Result<SubmergedVolumeCheck> volumeCheck(std::size_t body);

    const World& world() const { return *world_; }
    /// The scene as the world was last built from (settings changed since kept).
    const Scene& scene() const { return scene_; }
    const PreviewHistory& history() const { return history_; }
    const PreviewTimings& timings() const { return timings_; }
    std::string deviceName() const { return world_->backend().deviceName(); }
    std::size_t coveredTexels() const;

private:
    PreviewSession() = default;
    /// A world and the running sum of its backend's kernel time (ms).
    struct Built {
        std::unique_ptr<World> world;
        std::shared_ptr<double> kernelTotalMs;
    };
    static Result<Built> build(const Scene& scene, const std::string& device);
    Status advance();
    void record();
    /// Gives every body its forces: the floor as its resting contact (World::setContactForce:
    /// a body lying still on it may sleep) and, for the grabbed body, the spring as its
    /// external force (a push: it wakes the body and keeps it awake).
    void installForces();
    /// Body `body`'s grab spring: the spring while it is grabbed, none otherwise (the body
    /// wakes; no other does).
    void installSpring(std::size_t body);
    SeaFloor seaFloor_;
    /// What followDocument last saw of the document, per body: the material, the
    /// permeability, shell density and thickness images (null: no map) and the water graph
    /// with its settings (none: no graph).
    struct PaintSeen {
        MaterialDesc material;
        std::shared_ptr<const PaintedMap> permeability, shellDensity, shellThickness;
        std::optional<WaterGraph> graph;
        std::optional<WaterGraphDesc> graphSettings;
    };
    std::vector<PaintSeen> paintSeen_;
    std::vector<std::string> graphProblems_;  ///< per body: why its edited graph is held back
    Status checkEditedGraph(std::size_t body, const std::optional<WaterGraph>& graph);
    /// Per body, the hull's vertices (object space, without repeats): the floor's contacts.
    std::vector<std::vector<Eigen::Vector3d>> hullPoints_;
    Status swapIn(Built built);
    /// Rebuilds the world from scene_ (no bake), every body's graph holding the water it holds
    /// now, except `body`'s, which gets `graphNow` (null: none); carries states and time.
    Status rebuildCarryingWater(std::optional<std::size_t> body,
                                std::shared_ptr<const WaterGraph> graphNow);

    Scene scene_;  ///< as the world was last built (settings changed since kept)
    std::string device_;
    std::unique_ptr<World> world_;
    std::shared_ptr<double> kernelTotalMs_;  ///< summed by the world's backend wrapper
    bool playing_ = false;
    double timeScale_ = 1.0;
    double updateBudgetMs_ = kUpdateBudgetMs;
    double accumulator_ = 0.0;  ///< simulated seconds owed
    /// A rebuild on its worker thread (preview.cpp).
    struct RebuildJob;
    std::unique_ptr<RebuildJob> pending_;
    /// Cancelled rebuilds still winding down: joined once finished (never waited for by the
    /// UI), or in the destructor.
    std::vector<std::unique_ptr<RebuildJob>> abandoned_;
    std::string rebuildError_;
    void reapAbandoned();
    Status swapInRebuilt(RebuildJob& job);
    std::optional<std::size_t> grabbedBody_;
    Eigen::Vector3d grabObjectPoint_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d grabTarget_ = Eigen::Vector3d::Zero();
    double grabStiffness_ = 0, grabDamping_ = 0;
    Eigen::Vector3d grabImpulse_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d grabForceSum_ = Eigen::Vector3d::Zero();  ///< this frame's spring calls
    PreviewHistory history_;
    PreviewTimings timings_;
    /// The volume check's own backend (lazily, per body), so that the check never disturbs
    /// the simulation backend's timings.
    std::unique_ptr<BuoyancyBackend> checkBackend_;
    std::vector<std::size_t> checkIds_;
};

}  // namespace plimsoll::editor
