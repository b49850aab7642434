// The editor's live preview: a simulation session over a World built from the document's
// project (every body of it in one scene). No GL and no ImGui here: the panels drive it and the
// tests run it headless.
//  - play / pause / single step / reset, and a time scale; update() turns wall-clock time into
//    whole frames of project.simulation.timeStep through an accumulator whose catch-up is
//    capped, so a slow frame never freezes the UI in a spiral of ever more steps;
//  - the water model and the integrator change while it runs; a new physics texture size is
//    baked on a worker thread and swapped in (states and time carried over) when it is ready;
//  - a body can be grabbed: a spring from a point on the body to a target (the mouse ray),
//    applied as World's external force;
//  - a history of per-body quantities over time for the plots, exportable as CSV;
//  - the submerged-volume error against the exact clip at the current pose, by the function
//    `plimsoll buoyancy --compare-exact` uses (volume_check.h).
#pragma once

#include "plimsoll/project.h"
#include "plimsoll/result.h"
#include "plimsoll/volume_check.h"
#include "plimsoll/world.h"

#include <Eigen/Core>

#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll::editor {

/// The grab spring: F = k (target - p) - c v_p at the grabbed point p (world), torque
/// (p - c.o.m.) x F. Returned as a wrench about the centre of mass.
Wrench springWrench(const SimulatedBody& body, const RigidBodyState& state,
                    const Eigen::Vector3d& objectPoint, const Eigen::Vector3d& target,
                    double stiffness, double damping);

/// Heel and trim of an orientation, degrees: heel is the object z axis's rise (rotation about
/// the object x axis, starboard = +z down positive), trim the object x axis's rise (bow = +x up
/// positive).
Eigen::Vector2d heelAndTrimDegrees(const Eigen::Matrix3d& rotation);

/// Rotation -> degrees (rx, ry, rz) with R = Rz Ry Rx, as the project and the CLI take them.
Eigen::Vector3d eulerDegrees(const Eigen::Matrix3d& rotation);

/// One quantity over time: a column of a plot.
struct PlotSeries {
    std::string name;   ///< "buoy submerged volume"
    std::string unit;   ///< "m^3"
    std::vector<double> values;
};

/// The quantities recorded each frame, one row per frame; `time` is the simulated time (s).
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

    /// Builds the World (bakes every body) on this thread. `device` as createBuoyancyBackend
    /// takes it ("reference", "cpu", "gpu", an index, or empty for the default).
    static Result<std::unique_ptr<PreviewSession>> create(const Project& project,
                                                          const std::string& device);
    ~PreviewSession();

    void play() { playing_ = true; }
    void pause() { playing_ = false; }
    bool playing() const { return playing_; }
    /// One frame now, playing or paused.
    Status step();
    /// Back to the project's starting states at time 0; keeps the settings changed since
    /// (water, integrator, texture size), clears the history and releases a grab.
    Status reset();
    /// Simulated seconds per wall-clock second (0.01 .. 10).
    void setTimeScale(double scale);
    double timeScale() const { return timeScale_; }
    /// Advances by `wallSeconds` of wall-clock time times the time scale, in whole frames,
    /// at most kMaxCatchUpFrames and within kUpdateBudgetMs; nothing while paused. Also swaps in a finished rebuild.
    /// Returns the frames taken.
    Result<int> update(double wallSeconds);

    void setWater(const WaterModel& water);
    void setIntegrator(Integrator integrator);
    /// Rebakes every body at `size` texels a side on a worker thread; update() and step()
    /// swap the new world in when it is done. A second request replaces a pending one.
    void requestTextureSize(int size);
    bool rebuilding() const { return pending_.valid(); }
    /// Waits for a pending rebuild and swaps it in (tests, and before quitting).
    Status finishRebuild();
    /// The texture size the bodies have now (of body 0).
    int textureSize() const;

    /// Grabs body `body` at `objectPoint` (object space) and pulls it toward `target` (world)
    /// with a spring of `stiffness` (N/m; <= 0: the body's mass times (2 pi 1.5 Hz)^2) and
    /// critical damping for that stiffness.
    Status grab(std::size_t body, const Eigen::Vector3d& objectPoint,
                const Eigen::Vector3d& target, double stiffness = 0);
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
    /// project's mean level (volume_check.h; the same device kind as the simulation).
    Result<SubmergedVolumeCheck> volumeCheck(std::size_t body);

    const World& world() const { return *world_; }
    const Project& project() const { return project_; }
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
    static Result<Built> build(const Project& project, const std::string& device);
    Status advance();
    void record();
    void installGrab();
    Status swapIn(Built built);

    Project project_;            ///< as the world was last built (settings changed since kept)
    std::string device_;
    std::unique_ptr<World> world_;
    std::shared_ptr<double> kernelTotalMs_;  ///< summed by the world's backend wrapper
    bool playing_ = false;
    double timeScale_ = 1.0;
    double accumulator_ = 0.0;   ///< simulated seconds owed
    /// A rebuild on the worker thread (a plain struct: GCC 12 warns falsely on a Result
    /// crossing std::async).
    struct Rebuilt {
        Built built;
        std::string error;
    };
    std::future<Rebuilt> pending_;
    std::optional<std::size_t> grabbedBody_;
    Eigen::Vector3d grabObjectPoint_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d grabTarget_ = Eigen::Vector3d::Zero();
    double grabStiffness_ = 0, grabDamping_ = 0;
    Eigen::Vector3d grabImpulse_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d grabForceSum_ = Eigen::Vector3d::Zero();  ///< this frame's spring calls
    PreviewHistory history_;
    PreviewTimings timings_;
    /// The volume check's own backend and meshes (lazily, per body), so that the check never
    /// disturbs the simulation backend's timings.
    std::unique_ptr<BuoyancyBackend> checkBackend_;
    std::vector<std::size_t> checkIds_;
    std::vector<TriangleMesh> checkMeshes_;
};

}  // namespace plimsoll::editor
