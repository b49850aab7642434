// The editor's live preview session, headless: World's external-force hook against the
// momentum it must add, play / pause / step / reset and the time scale in frames, the grab
// spring (the body moves toward the target; momentum change = gravity's impulse + the spring's),
// settings changed while running, CSV export read back, and the live submerged-volume error
// against what `plimsoll buoyancy --compare-exact` prints for the same pose.
#include "document/preview.h"
#include "render/force_overlay.h"

#include "cli_runner.h"
#include "test_support.h"

#include "plimsoll/primitives.h"
#include "plimsoll/world.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace plimsoll::editor {
namespace {

namespace fs = std::filesystem;

/// A ball of density 500 in fresh water; `waterLevel` far below keeps it in the air.
Project ballProject(double waterLevel, const Eigen::Vector3d& gravity) {
    Project project;
    project.folder = fs::temp_directory_path();
    BodyDesc body;
    body.name = "ball";
    body.mesh = test::assetPath("sphere.obj").string();
    body.textureSize = 64;
    body.material.density = 500.0;
    body.position = Eigen::Vector3d(0.2, 0.3, -0.1);
    project.bodies.push_back(body);
    project.water = WaterModel::flat(waterLevel);
    project.simulation.gravity = gravity;
    return project;
}

std::unique_ptr<PreviewSession> makeSession(const Project& project) {
    Result<std::unique_ptr<PreviewSession>> s = PreviewSession::create(project, "reference");
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    return s.ok() ? std::move(*s) : nullptr;
}

TEST(WorldExternalForce, AddsItsImpulseToTheMomentaAndCanBeRemoved) {
    const Eigen::Vector3d g(0, -9.81, 0);
    Result<std::unique_ptr<World>> made =
        World::create(ballProject(-100.0, g), createReferenceBackend());
    ASSERT_TRUE(made.ok()) << made.error().message;
    World& world = **made;
    const double m = world.bodies()[0].mass.mass;
    const double T = world.project().simulation.timeStep;
    const Eigen::Vector3d force(3.0, 40.0, -7.0), torque(0.5, -0.25, 2.0);
    int calls = 0;
    ASSERT_TRUE(world.setExternalForce(0, [&](const SimulatedBody&, const RigidBodyState&) {
        ++calls;
        return Wrench{force, torque};
    }).ok());
    const RigidBodyState before = world.bodies()[0].state;
    ASSERT_TRUE(world.advanceFrame().ok());
    const RigidBodyState after = world.bodies()[0].state;
    EXPECT_EQ(static_cast<std::size_t>(calls), world.statistics().steps);  // once a step
    // Out of the water: gravity and the external force are all there is.
    EXPECT_LT((after.linearMomentum - before.linearMomentum - (m * g + force) * T).norm(), 1e-9);
    EXPECT_LT((after.angularMomentum - before.angularMomentum - torque * T).norm(), 1e-9);

    ASSERT_TRUE(world.setExternalForce(0, {}).ok());
    const RigidBodyState again = world.bodies()[0].state;
    ASSERT_TRUE(world.advanceFrame().ok());
    EXPECT_LT((world.bodies()[0].state.linearMomentum - again.linearMomentum - m * g * T).norm(), 1e-9);
    EXPECT_FALSE(world.setExternalForce(5, {}).ok());
}

TEST(PreviewSession, PlayPauseStepResetAndTimeScaleCountFrames) {
    auto session = makeSession(ballProject(0.0, Eigen::Vector3d(0, -9.81, 0)));
    ASSERT_TRUE(session);
    const double T = session->project().simulation.timeStep;
    const RigidBodyState start = session->world().bodies()[0].state;

    // Paused: wall time passes, nothing moves.
    EXPECT_FALSE(session->playing());
    ASSERT_TRUE(session->update(1.0).ok());
    EXPECT_EQ(session->world().time(), 0.0);
    // A single step is one frame, paused or not.
    ASSERT_TRUE(session->step().ok());
    EXPECT_NEAR(session->world().time(), T, 1e-12);
    EXPECT_EQ(session->history().time.size(), 2u);  // the start and one frame
    // The frame's sub-steps (at least the project's), each one evaluation of the backend.
    EXPECT_GE(session->timings().subSteps, session->project().simulation.subSteps);
    EXPECT_GE(session->timings().kernelMs, 0.0);

    // Playing: whole frames of the wall time, the remainder owed to the next update.
    session->play();
    Result<int> frames = session->update(2.5 * T);
    ASSERT_TRUE(frames.ok());
    EXPECT_EQ(*frames, 2);
    frames = session->update(0.5 * T);
    EXPECT_EQ(*frames, 1);
    EXPECT_NEAR(session->world().time(), 4 * T, 1e-12);
    // Half speed: four frames of wall time are two simulated frames.
    session->setTimeScale(0.5);
    frames = session->update(4 * T);
    EXPECT_EQ(*frames, 2);
    // A long stall catches up at most kMaxCatchUpFrames and drops the rest.
    session->setTimeScale(1.0);
    frames = session->update(1.0);
    EXPECT_EQ(*frames, PreviewSession::kMaxCatchUpFrames);
    EXPECT_GT(session->timings().droppedFrames, 40);
    const double played = session->world().time();
    EXPECT_NEAR(played, (6 + PreviewSession::kMaxCatchUpFrames) * T, 1e-12);
    EXPECT_NE(session->world().bodies()[0].state.position, start.position);
    session->pause();
    EXPECT_EQ(*session->update(1.0), 0);

    // Reset: the starting state at time 0, the history started over.
    ASSERT_TRUE(session->reset().ok());
    EXPECT_EQ(session->world().time(), 0.0);
    EXPECT_LT((session->world().bodies()[0].state.position - start.position).norm(), 1e-12);
    EXPECT_LT((session->world().bodies()[0].state.linearMomentum - start.linearMomentum).norm(), 1e-12);
    EXPECT_EQ(session->history().time.size(), 1u);
}

TEST(PreviewSession, GrabSpringPullsTheBodyTowardTheTargetAndItsImpulseIsTheMomentumChange) {
    const Eigen::Vector3d g(0, -9.81, 0);
    auto session = makeSession(ballProject(-100.0, g));
    ASSERT_TRUE(session);
    const SimulatedBody& body = session->world().bodies()[0];
    const double m = body.mass.mass;
    const Eigen::Vector3d centre = body.mass.centerOfMass;  // object space
    const Eigen::Vector3d startPosition = body.state.position;
    const Eigen::Vector3d startMomentum = body.state.linearMomentum;
    const Eigen::Vector3d target = startPosition + Eigen::Vector3d(1.0, 0.5, 0.0);
    // Grabbed at the centre of mass: a pure force (the default stiffness, a 1.5 Hz spring for
    // the body's mass, critically damped).
    ASSERT_TRUE(session->grab(0, centre, target).ok());
    EXPECT_LT((session->grabPoint() - startPosition).norm(), 1e-12);
    const int frames = 30;
    for (int i = 0; i < frames; ++i) ASSERT_TRUE(session->step().ok());
    const SimulatedBody& moved = session->world().bodies()[0];
    // It moved toward the target (against gravity too: the spring is much stronger).
    EXPECT_LT((moved.state.position - target).norm(), 0.5 * (startPosition - target).norm());
    const double T = frames * session->project().simulation.timeStep;
    const Eigen::Vector3d expected = m * g * T + session->grabImpulse();
    EXPECT_LT((moved.state.linearMomentum - startMomentum - expected).norm(),
              1e-9 * std::max(1.0, expected.norm()));
    EXPECT_GT(session->grabImpulse().norm(), 1.0);
    // The spring alone, by hand, at the end state: k (target - p) - c v.
    const Wrench w = springWrench(moved, moved.state, centre, target, 2000.0, 0.0);
    EXPECT_LT((w.force - 2000.0 * (target - moved.state.position)).norm(), 1e-9);
    EXPECT_LT(w.torque.norm(), 1e-9);

    // Released: gravity alone again.
    session->release();
    const Eigen::Vector3d p0 = session->world().bodies()[0].state.linearMomentum;
    ASSERT_TRUE(session->step().ok());
    EXPECT_LT((session->world().bodies()[0].state.linearMomentum - p0 -
               m * g * session->project().simulation.timeStep).norm(), 1e-9);
}

TEST(PreviewSession, OffCentreGrabTurnsTheBody) {
    auto session = makeSession(ballProject(-100.0, Eigen::Vector3d::Zero()));
    ASSERT_TRUE(session);
    const SimulatedBody& body = session->world().bodies()[0];
    const Eigen::Vector3d point = body.mass.centerOfMass + Eigen::Vector3d(0, 0.4, 0);
    const Eigen::Vector3d grabbed = body.pose().apply(point);
    ASSERT_TRUE(session->grab(0, point, grabbed + Eigen::Vector3d(0.5, 0, 0)).ok());
    ASSERT_TRUE(session->step().ok());
    // A pull along +x above the centre: torque (0, 0.4, 0) x (F, 0, 0) = -0.4 F z.
    EXPECT_LT(session->world().bodies()[0].state.angularMomentum.z(), 0.0);
    EXPECT_GT(session->world().bodies()[0].state.linearMomentum.x(), 0.0);
}

TEST(PreviewSession, WaterIntegratorAndTextureSizeChangeWhileRunning) {
    auto session = makeSession(ballProject(0.0, Eigen::Vector3d(0, -9.81, 0)));
    ASSERT_TRUE(session);
    ASSERT_TRUE(session->step().ok());
    const double wet = session->world().bodies()[0].buoyancy.submergedVolume;
    EXPECT_GT(wet, 0.0);
    // The water raised above the ball: the next frame sees it fully under.
    session->setWater(WaterModel::flat(5.0));
    ASSERT_TRUE(session->step().ok());
    EXPECT_GT(session->world().bodies()[0].buoyancy.submergedVolume, 1.5 * wet);
    EXPECT_EQ(session->world().project().water.level, 5.0);

    session->setIntegrator(Integrator::RK4);
    ASSERT_TRUE(session->step().ok());
    EXPECT_EQ(session->world().project().simulation.integrator, Integrator::RK4);
    EXPECT_GT(session->world().bodies()[0].buoyancy.submergedVolume, 0.0);  // RK4 fills it too

    const std::size_t texels = session->coveredTexels();
    const Eigen::Vector3d position = session->world().bodies()[0].state.position;
    const double time = session->world().time();
    session->requestTextureSize(32);
    EXPECT_TRUE(session->rebuilding());
    ASSERT_TRUE(session->finishRebuild().ok());
    EXPECT_FALSE(session->rebuilding());
    EXPECT_EQ(session->textureSize(), 32);
    EXPECT_LT(session->coveredTexels(), texels);
    EXPECT_EQ(session->world().time(), time);  // carried over
    EXPECT_EQ(session->world().bodies()[0].state.position, position);
    EXPECT_EQ(session->world().project().water.level, 5.0);  // settings kept
    EXPECT_EQ(session->world().project().simulation.integrator, Integrator::RK4);
    ASSERT_TRUE(session->step().ok());
}

TEST(PreviewSession, HistoryExportsAsCsvThatReadsBack) {
    auto session = makeSession(ballProject(0.0, Eigen::Vector3d(0, -9.81, 0)));
    ASSERT_TRUE(session);
    for (int i = 0; i < 12; ++i) ASSERT_TRUE(session->step().ok());
    const PreviewHistory& h = session->history();
    ASSERT_EQ(h.time.size(), 13u);
    const PlotSeries* volume = h.find("ball submerged volume");
    ASSERT_TRUE(volume);
    ASSERT_TRUE(h.find("ball heel") && h.find("ball trim") && h.find("ball buoyancy"));
    const fs::path path = fs::temp_directory_path() / ("preview_" + std::to_string(::getpid()) + ".csv");
    ASSERT_TRUE(writeHistoryCsv(h, {"ball submerged volume", "ball height"}, path).ok());
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "time (s),\"ball submerged volume (m^3)\",\"ball height (m)\"");
    std::size_t rows = 0;
    while (std::getline(in, line)) {
        double t = 0, v = 0, y = 0;
        ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &t, &v, &y), 3) << line;
        EXPECT_EQ(t, h.time[rows]);
        EXPECT_EQ(v, volume->values[rows]);
        EXPECT_EQ(y, h.find("ball height")->values[rows]);
        ++rows;
    }
    EXPECT_EQ(rows, h.time.size());
    const Status bad = writeHistoryCsv(h, {"no such thing"}, path);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("no such thing"), std::string::npos);
    fs::remove(path);
}

TEST(PreviewSession, HeelAndTrimOfKnownRotations) {
    using Eigen::AngleAxisd;
    using Eigen::Vector3d;
    const Eigen::Vector2d heel =
        heelAndTrimDegrees(AngleAxisd(0.3, Vector3d::UnitX()).toRotationMatrix());
    EXPECT_NEAR(heel.x(), 0.3 * 180 / M_PI, 1e-9);
    EXPECT_NEAR(heel.y(), 0.0, 1e-9);
    const Eigen::Vector2d trim =
        heelAndTrimDegrees(AngleAxisd(0.2, Vector3d::UnitZ()).toRotationMatrix());
    EXPECT_NEAR(trim.x(), 0.0, 1e-9);
    EXPECT_NEAR(trim.y(), 0.2 * 180 / M_PI, 1e-9);
    const Vector3d degrees(10, -20, 30);
    const Pose pose = Pose::fromEulerDegrees(Vector3d::Zero(), degrees);
    EXPECT_LT((eulerDegrees(pose.rotation) - degrees).norm(), 1e-9);
}

TEST(PreviewSession, LiveVolumeErrorEqualsWhatPlimsollBuoyancyPrints) {
    Result<Project> project = loadProject(fs::path(PLIMSOLL_SOURCE_DIR) / "projects/buoy.plim.json");
    ASSERT_TRUE(project.ok()) << project.error().message;
    // Dropped from above and tilted: a pose out of equilibrium, partly submerged.
    project->bodies[0].position = Eigen::Vector3d(0.1, 0.6, -0.2);
    project->bodies[0].rotationDegrees = Eigen::Vector3d(12, 0, 5);
    auto session = makeSession(*project);
    ASSERT_TRUE(session);
    for (int i = 0; i < 20; ++i) ASSERT_TRUE(session->step().ok());
    Result<SubmergedVolumeCheck> live = session->volumeCheck(0);
    ASSERT_TRUE(live.ok()) << live.error().message;
    ASSERT_GT(live->exact, 0.0);

    const Pose pose = session->world().bodies()[0].pose();
    const Eigen::Vector3d degrees = eulerDegrees(pose.rotation);
    char args[512];
    std::snprintf(args, sizeof args,
                  "buoyancy '%s' --size %d --device reference --water-level=%.17g "
                  "--position=%.17g,%.17g,%.17g --rotation-deg=%.17g,%.17g,%.17g "
                  "--fluid-density %.17g --compare-exact --json",
                  (fs::path(PLIMSOLL_SOURCE_DIR) / "assets/buoy.obj").c_str(),
                  project->bodies[0].textureSize, project->water.level,
                  pose.translation.x(), pose.translation.y(), pose.translation.z(), degrees.x(),
                  degrees.y(), degrees.z(), project->medium.density);
    const test::CommandOutput cli = test::runPlimsoll(args);
    ASSERT_EQ(cli.exitCode, 0) << cli.err;
    const nlohmann::json printed = nlohmann::json::parse(cli.out);
    const double tolerance = 1e-9 * live->exact;
    EXPECT_NEAR(printed["submerged_volume"].get<double>(), live->texture, tolerance);
    EXPECT_NEAR(printed["exact_submerged_volume"].get<double>(), live->exact, tolerance);
    EXPECT_NEAR(printed["submerged_volume_error"].get<double>(), live->error, tolerance);
    EXPECT_NEAR(printed["submerged_volume_relative_error"].get<double>(), live->relativeError, 1e-9);
    // And the figure means something: a 128^2 bake is within a few percent of exact.
    EXPECT_LT(std::abs(live->relativeError), 0.05);
    std::cout << "buoy 128^2 submerged volume " << live->texture << " m^3, exact " << live->exact
              << ", error " << 100 * live->relativeError << " %\n";
}

TEST(ForceOverlay, WaterlineOfABoxIsItsPerimeterAtTheWaterHeight) {
    const TriangleMesh box = makeBox(Eigen::Vector3d(1.0, 0.6, 2.0));
    // Turned about y (the waterline stays a 1 x 2 rectangle), raised so the water at 0.1 cuts it.
    const Pose pose = Pose::fromEulerDegrees(Eigen::Vector3d(3, 0.05, -1), Eigen::Vector3d(0, 35, 0));
    const std::vector<OverlaySegment> line = waterlineOf(box, pose, WaterModel::flat(0.1), 0.0);
    double length = 0;
    for (const OverlaySegment& s : line) {
        EXPECT_NEAR(s.a.y(), 0.1, 1e-12);
        EXPECT_NEAR(s.b.y(), 0.1, 1e-12);
        length += (s.b - s.a).norm();
    }
    EXPECT_NEAR(length, 2 * (1.0 + 2.0), 1e-9);
    // Out of the water: no line.
    EXPECT_TRUE(waterlineOf(box, pose, WaterModel::flat(-5.0), 0.0).empty());
}

TEST(ForceOverlay, ArrowsAreWeightAtTheCentreOfMassAndBuoyancyInProportion) {
    auto session = makeSession(ballProject(0.0, Eigen::Vector3d(0, -9.81, 0)));
    ASSERT_TRUE(session);
    ASSERT_TRUE(session->step().ok());
    const World& world = session->world();
    const SimulatedBody& body = world.bodies()[0];
    const ForceOverlay overlay = buildForceOverlay(world, {nullptr});
    const OverlayArrow* weight = nullptr;
    const OverlayArrow* buoyancy = nullptr;
    for (const OverlayArrow& a : overlay.arrows) {
        if (a.colour == kWeightColour) weight = &a;
        if (a.colour == kBuoyancyColour) buoyancy = &a;
    }
    ASSERT_TRUE(weight && buoyancy);
    EXPECT_LT((weight->from - body.state.position).norm(), 1e-12);
    // The weight's arrow is half the bounding radius long, straight down.
    EXPECT_LT((weight->to - weight->from - Eigen::Vector3d(0, -0.5 * body.boundingRadius, 0)).norm(), 1e-9);
    EXPECT_LT((buoyancy->from - body.buoyancy.centerOfBuoyancy).norm(), 1e-12);
    const double ratio = body.buoyancy.force.norm() / (body.mass.mass * 9.81);
    EXPECT_NEAR((buoyancy->to - buoyancy->from).norm(), 0.5 * ratio * body.boundingRadius, 1e-9);
    EXPECT_GT((buoyancy->to - buoyancy->from).y(), 0.0);
}

TEST(ForceOverlay, WetTexelsAreTheSubmergedShareOfTheSurface) {
    // The ball with its centre on flat water.
    auto session = makeSession(ballProject(0.0, Eigen::Vector3d(0, -9.81, 0)));
    ASSERT_TRUE(session);
    SimulatedBody body = session->world().bodies()[0];  // a copy to place by hand
    body.state.position = body.mass.centerOfMass;      // the sphere's centre on the water
    body.state.orientation = Eigen::Quaterniond::Identity();
    const OverlayImage image = wetTexelOverlay(body, WaterModel::flat(0.0), 0.0);
    ASSERT_EQ(image.width, body.textures.size);
    double wet = 0, total = 0;
    const Eigen::Vector3i wetColour = (kWetColour * 255.0f).array().round().cast<int>();
    for (std::size_t i = 0; i < body.textures.coveredCount(); ++i) {
        const std::size_t texel = body.textures.texelIndex[i];
        const bool isWet = image.rgba[4 * texel] == wetColour.x() &&
                           image.rgba[4 * texel + 1] == wetColour.y();
        total += body.textures.area[i];
        wet += isWet ? body.textures.area[i] : 0.0;
    }
    // A sphere cut through its centre: half its surface below (texels straddling the line
    // count whole, on either side).
    EXPECT_NEAR(wet / total, 0.5, 0.03);
}

}  // namespace
}  // namespace plimsoll::editor
