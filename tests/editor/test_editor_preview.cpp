// The editor's live preview session, headless: play / pause / step / reset and the time scale
// in frames, the grab spring (the body moves toward the target; momentum change = gravity's
// impulse + the spring's), settings changed while running, CSV export read back, and the live
// submerged-volume error against what `plimsoll buoyancy --compare-exact` prints for the same pose.
#include "document/command.h"
#include "document/document.h"
#include "document/graph_edit.h"
#include "document/preview.h"
#include "view/force_overlay.h"

#include "cli_runner.h"
#include "document_test_support.h"
#include "test_support.h"
#include "world_support.h"

#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/world.h"

#include <limits>
#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <thread>
#include <unistd.h>

namespace plimsoll::editor {
namespace test_editor_preview {
namespace {

namespace fs = std::filesystem;

using test::ballProject;

std::unique_ptr<PreviewSession> makeSession(const Project& project) {
    Result<std::unique_ptr<PreviewSession>> s =
        PreviewSession::create(test::sceneOrFail(project), "reference");
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    return s.ok() ? std::move(*s) : nullptr;
}

TEST(PreviewSession, PlayPauseStepResetAndTimeScaleCountFrames) {
    auto session = makeSession(ballProject(0.0, Eigen::Vector3d(0, -9.81, 0)));
    ASSERT_TRUE(session);
    const double T = session->scene().simulation.timeStep;
    const RigidBodyState start = session->world().bodies()[0].state;

    // Paused: wall time passes, nothing moves.
    EXPECT_FALSE(session->playing());
    ASSERT_TRUE(session->update(1.0).ok());
    EXPECT_EQ(session->world().time(), 0.0);
    // A single step is one frame, paused or not.
    ASSERT_TRUE(session->step().ok());
    EXPECT_NEAR(session->world().time(), T, 1e-12);
    EXPECT_EQ(session->history().time.size(), 1u);  // the frame (none before it)
    // The frame's sub-steps (at least the project's), each one evaluation of the backend.
    EXPECT_GE(session->timings().subSteps, session->scene().simulation.subSteps);
    EXPECT_GE(session->timings().kernelMs, 0.0);

    // Playing: whole frames of the wall time, the remainder owed to the next update. No
    // wall-clock budget while frames are counted (a slow build would stop a catch-up early);
    // the budget is checked on its own below.
    session->setUpdateBudgetMs(std::numeric_limits<double>::infinity());
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
    // A budget already spent after the first frame: one frame however much time is owed.
    session->setUpdateBudgetMs(0.0);
    EXPECT_EQ(*session->update(1.0), 1);
    EXPECT_NEAR(session->world().time(), played + T, 1e-12);
    session->setUpdateBudgetMs(PreviewSession::kUpdateBudgetMs);
    session->pause();
    EXPECT_EQ(*session->update(1.0), 0);

    // Reset: the starting state at time 0, the history started over.
    ASSERT_TRUE(session->reset().ok());
    EXPECT_EQ(session->world().time(), 0.0);
    EXPECT_LT((session->world().bodies()[0].state.position - start.position).norm(), 1e-12);
    EXPECT_LT((session->world().bodies()[0].state.linearMomentum - start.linearMomentum).norm(),
              1e-12);
    EXPECT_TRUE(session->history().time.empty());
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
    const double T = frames * session->scene().simulation.timeStep;
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
               m * g * session->scene().simulation.timeStep)
                  .norm(),
              1e-9);
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

/// A steel-dense box (assets/box.obj, 1 x 0.5 x 0.25 m) that sinks in flat water at 0, tipped
/// 25 degrees about x and 10 about z so that it meets the floor with one corner.
Project sinkingBox() {
    Project project = ballProject(0.0, Eigen::Vector3d(0, -9.81, 0));
    project.bodies[0].name = "box";
    project.bodies[0].mesh = test::assetPath("box.obj").string();
    project.bodies[0].material.density = 3000.0;
    project.bodies[0].rotationDegrees = Eigen::Vector3d(25.0, 0.0, 10.0);
    return project;
}

TEST(PreviewSession, SinkingBoxComesToRestOnTheSeaFloor) {
    auto session = makeSession(sinkingBox());
    ASSERT_TRUE(session);
    ASSERT_FALSE(session->floorHeight());  // off unless asked for
    session->setSeaFloor(SeaFloor{.enabled = true, .depth = 2.0});
    ASSERT_TRUE(session->floorHeight());
    EXPECT_DOUBLE_EQ(*session->floorHeight(), -2.0);
    for (int i = 0; i < 600; ++i) ASSERT_TRUE(session->step().ok());  // 10 s
    const SimulatedBody& box = session->world().bodies()[0];
    // Resting on the floor: its lowest corner at the floor's depth (pressed into it by its
    // weight less its buoyancy over the contact's stiffness, about a centimetre)...
    EXPECT_NEAR(session->lowestPoint(0), -2.0, 0.02);
    // ...still, and turned flat onto a face (a corner first met the floor): one of the box's
    // axes vertical, its centre half the box's size along that axis above the floor.
    EXPECT_LT(linearVelocity(box.state, box.mass).norm(), 0.01);
    EXPECT_LT(angularVelocity(box.state, box.mass).norm(), 0.02);
    const Eigen::Matrix3d r = box.pose().rotation;
    Eigen::Index up = 0;
    EXPECT_GT(r.row(1).cwiseAbs().maxCoeff(&up), 0.999) << r;
    const double halfSizes[] = {0.5, 0.25, 0.125};
    EXPECT_NEAR(box.state.position.y(), -2.0 + halfSizes[up], 0.02) << "on axis " << up;
    // Moved up, the floor carries it again.
    session->setSeaFloor(SeaFloor{.enabled = true, .depth = 1.5});
    for (int i = 0; i < 300; ++i) ASSERT_TRUE(session->step().ok());
    EXPECT_NEAR(session->lowestPoint(0), -1.5, 0.02);
}

TEST(PreviewSession, BoxAtRestOnTheSeaFloorSleepsAndAGrabWakesIt) {
    // The floor holds the box up with a force that never vanishes; it is a resting contact,
    // not a push: once the box lies still on it for the rest time it sleeps, and asleep it
    // holds its pose exactly. A grab wakes it and lifts it; let go, it settles and sleeps again.
    auto session = makeSession(sinkingBox());
    ASSERT_TRUE(session);
    session->setSeaFloor(SeaFloor{.enabled = true, .depth = 2.0});
    const auto asleep = [&] { return session->world().bodies()[0].asleep; };
    int frames = 0;
    for (; frames < 20 * 60 && !asleep(); ++frames) ASSERT_TRUE(session->step().ok());
    ASSERT_TRUE(asleep()) << "not asleep after 20 s; lowest point " << session->lowestPoint(0);
    const double sleptAt = session->world().time();
    EXPECT_LT(sleptAt, 12.0);  // sinks (about 3 s), tips flat, then rests the rest time (2 s)
    EXPECT_NEAR(session->lowestPoint(0), -2.0, 0.02);
    const RigidBodyState rest = session->world().bodies()[0].state;
    const std::size_t sleeping = session->world().statistics().sleepingBodyFrames;
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(session->step().ok());
    EXPECT_TRUE(asleep());
    EXPECT_EQ(session->world().bodies()[0].state.position, rest.position);
    EXPECT_EQ(session->world().statistics().sleepingBodyFrames, sleeping + 60);
    // Grabbed at its centre and pulled 1 m up: awake from the next frame, and rising.
    const Eigen::Vector3d centre = session->world().bodies()[0].state.position;
    ASSERT_TRUE(session
                    ->grab(0, session->world().bodies()[0].mass.centerOfMass,
                           centre + Eigen::Vector3d(0, 1, 0))
                    .ok());
    ASSERT_TRUE(session->step().ok());
    EXPECT_FALSE(asleep());
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(session->step().ok());
    EXPECT_GT(session->world().bodies()[0].state.position.y(), centre.y() + 0.2);
    session->release();
    for (frames = 0; frames < 20 * 60 && !asleep(); ++frames) ASSERT_TRUE(session->step().ok());
    EXPECT_TRUE(asleep());
    EXPECT_NEAR(session->lowestPoint(0), -2.0, 0.02);
    // New water wakes it too.
    session->setWater(WaterModel::flat(0.5));
    ASSERT_TRUE(session->step().ok());
    EXPECT_FALSE(asleep());
}

TEST(PreviewSession, AGrabWakesTheGrabbedBodyAndNoOther) {
    // Two boxes 4 m apart at rest on the sea floor, both asleep. Grabbing one wakes it alone:
    // the other keeps its pose exactly and sleeps on, through the grab and the release.
    Project project = sinkingBox();
    project.bodies.push_back(project.bodies[0]);
    project.bodies[1].name = "box 2";
    project.bodies[1].position = project.bodies[0].position + Eigen::Vector3d(4.0, 0, 0);
    auto session = makeSession(project);
    ASSERT_TRUE(session);
    session->setSeaFloor(SeaFloor{.enabled = true, .depth = 2.0});
    const auto asleep = [&](std::size_t i) { return session->world().bodies()[i].asleep; };
    for (int f = 0; f < 20 * 60 && !(asleep(0) && asleep(1)); ++f)
        ASSERT_TRUE(session->step().ok());
    ASSERT_TRUE(asleep(0) && asleep(1)) << "not both asleep after 20 s";
    const RigidBodyState rest = session->world().bodies()[1].state;
    const std::size_t wakeUps = session->world().statistics().wakeUps;
    const Eigen::Vector3d centre = session->world().bodies()[0].state.position;
    ASSERT_TRUE(session
                    ->grab(0, session->world().bodies()[0].mass.centerOfMass,
                           centre + Eigen::Vector3d(0, 1, 0))
                    .ok());
    for (int i = 0; i < 30; ++i) ASSERT_TRUE(session->step().ok());
    EXPECT_FALSE(asleep(0));
    EXPECT_GT(session->world().bodies()[0].state.position.y(), centre.y() + 0.05);
    EXPECT_TRUE(asleep(1)) << "the grab woke the other box";
    EXPECT_EQ(session->world().statistics().wakeUps, wakeUps + 1);
    session->release();
    ASSERT_TRUE(session->step().ok());
    EXPECT_TRUE(asleep(1)) << "the release woke the other box";
    EXPECT_EQ(session->world().bodies()[1].state.position, rest.position);
    EXPECT_EQ(session->world().statistics().wakeUps, wakeUps + 1);
}

TEST(PreviewSession, WithoutTheSeaFloorTheBoxKeepsSinking) {
    auto session = makeSession(sinkingBox());
    ASSERT_TRUE(session);
    for (int i = 0; i < 600; ++i) ASSERT_TRUE(session->step().ok());
    const double after10 = session->lowestPoint(0);
    EXPECT_LT(after10, -5.0);
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(session->step().ok());
    EXPECT_LT(session->lowestPoint(0), after10 - 0.5);  // still going down, fast
    // Switched on below the box, it stops there; switched off, the box sinks on.
    session->setSeaFloor(SeaFloor{.enabled = true, .depth = -session->lowestPoint(0) + 1.0});
    const double floorY = *session->floorHeight();
    for (int i = 0; i < 600; ++i) ASSERT_TRUE(session->step().ok());
    EXPECT_NEAR(session->lowestPoint(0), floorY, 0.02);
    session->setSeaFloor(SeaFloor{.enabled = false});
    for (int i = 0; i < 120; ++i) ASSERT_TRUE(session->step().ok());
    EXPECT_LT(session->lowestPoint(0), floorY - 1.0);
}

TEST(PreviewSession, DamagedBoatFloodsSinksAndRestsOnTheSeaFloor) {
    Result<std::unique_ptr<Document>> opened =
        Document::open(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / "damaged_boat.plim.json");
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    Result<Scene> scene = (*opened)->simulationScene();
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    Result<std::unique_ptr<PreviewSession>> made = PreviewSession::create(std::move(*scene), "");
    ASSERT_TRUE(made.ok()) << made.error().message;
    PreviewSession& session = **made;
    session.setSeaFloor(SeaFloor{.enabled = true, .depth = 3.0});
    // It floods through the stern and goes down within two minutes (the stern meets the
    // floor first, the bow swings down after it); then it lies still for two seconds.
    int still = 0;
    for (int frame = 0; frame < 120 * 60 && still < 120; ++frame) {
        ASSERT_TRUE(session.step().ok());
        const SimulatedBody& b = session.world().bodies()[0];
        still = session.lowestPoint(0) < -2.9 && linearVelocity(b.state, b.mass).norm() < 0.01 &&
                        angularVelocity(b.state, b.mass).norm() < 0.02
                    ? still + 1
                    : 0;
    }
    EXPECT_EQ(still, 120) << "t = " << session.world().time() << " s, lowest point "
                          << session.lowestPoint(0);
    EXPECT_NEAR(session.lowestPoint(0), -3.0, 0.02);
    const SimulatedBody& boat = session.world().bodies()[0];
    EXPECT_LT(linearVelocity(boat.state, boat.mass).norm(), 0.01);
    // Lying there, its flooding over, it sleeps within 10 s, the floor holding it up.
    for (int frame = 0; frame < 10 * 60 && !boat.asleep; ++frame) ASSERT_TRUE(session.step().ok());
    EXPECT_TRUE(session.world().bodies()[0].asleep) << "water " << boat.water;
}

/// A preview of the document as it is now, on the default device (the editor's).
std::unique_ptr<PreviewSession> sessionOf(const Document& document) {
    Result<Scene> scene = document.simulationScene();
    EXPECT_TRUE(scene.ok()) << scene.error().message;
    if (!scene) return nullptr;
    Result<std::unique_ptr<PreviewSession>> made = PreviewSession::create(std::move(*scene), "");
    EXPECT_TRUE(made.ok()) << made.error().message;
    return made ? std::move(*made) : nullptr;
}

/// A sample project open in a document, a session that follows the document and a twin that
/// does not, both stepped `frames` frames: what each edit-during-preview test starts from.
struct Twins {
    std::unique_ptr<Document> doc;
    std::unique_ptr<PreviewSession> session, twin;
    explicit operator bool() const { return doc && session && twin; }
};
Twins twinsOf(const std::string& project, int frames) {
    Twins t;
    t.doc = test::openOrFail(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / project);
    if (!t.doc) return t;
    t.session = sessionOf(*t.doc);
    t.twin = sessionOf(*t.doc);
    if (!t.session || !t.twin) return t;
    EXPECT_TRUE(t.session->followDocument(*t.doc).ok());
    for (int i = 0; i < frames; ++i) {
        if (!t.session->step().ok() || !t.twin->step().ok()) {
            ADD_FAILURE() << project << ": step " << i << " failed";
            t.twin.reset();
            return t;
        }
    }
    return t;
}

TEST(PreviewSession, PaintedDensityChangesTheMassOnTheNextFrame) {
    std::unique_ptr<Document> doc =
        test::openOrFail(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / "buoy.plim.json");
    ASSERT_TRUE(doc);
    auto session = sessionOf(*doc), twin = sessionOf(*doc);
    ASSERT_TRUE(session && twin);
    Result<std::vector<std::size_t>> seen = session->followDocument(*doc);
    ASSERT_TRUE(seen.ok()) << seen.error().message;
    EXPECT_TRUE(seen->empty());  // the first call notes what the preview started from
    for (int i = 0; i < 30; ++i) ASSERT_TRUE(session->step().ok() && twin->step().ok());
    const double before = session->world().bodies()[0].mass.mass;
    // The ballast painted over the whole shell, at full density, while the preview runs.
    test::executeOrFail(*doc, makeFillAllCommand(*doc, 0, MapChannel::Density, 1.0));
    seen = session->followDocument(*doc);
    ASSERT_TRUE(seen.ok()) << seen.error().message;
    EXPECT_EQ(*seen, std::vector<std::size_t>{0});
    // The mass is the edited document's, at once: that of a preview started from it.
    auto fresh = sessionOf(*doc);
    ASSERT_TRUE(fresh);
    const double after = session->world().bodies()[0].mass.mass;
    EXPECT_GT(after, before * 1.05);
    EXPECT_NEAR(after, fresh->world().bodies()[0].mass.mass, 1e-9 * after);
    // The next frame's forces differ from those of the twin that did not follow.
    const Eigen::Vector3d p0 = session->world().bodies()[0].state.linearMomentum;
    const Eigen::Vector3d q0 = twin->world().bodies()[0].state.linearMomentum;
    EXPECT_LT((p0 - q0).norm(), 1e-12);  // the same state until then
    ASSERT_TRUE(session->step().ok() && twin->step().ok());
    const double dt = session->scene().simulation.timeStep;
    const Eigen::Vector3d force = (session->world().bodies()[0].state.linearMomentum - p0) / dt;
    const Eigen::Vector3d twinForce = (twin->world().bodies()[0].state.linearMomentum - q0) / dt;
    // Heavier by (after - before): that much more weight.
    EXPECT_NEAR(force.y() - twinForce.y(), -(after - before) * 9.81,
                0.05 * (after - before) * 9.81);
    // Nothing changed since: nothing to take.
    seen = session->followDocument(*doc);
    ASSERT_TRUE(seen.ok());
    EXPECT_TRUE(seen->empty());
}

TEST(PreviewSession, PaintedThicknessChangesTheMassOnTheNextFrame) {
    // The buoy: a solid of 150 kg/m^3 and a ballasted shell (its density map). A thickness map
    // filled at one half while the preview runs halves the shell: the mass becomes the solid's
    // plus half the shell's, at once, and the next frame's weight is lighter by the difference.
    Twins t = twinsOf("buoy.plim.json", 30);
    ASSERT_TRUE(t);
    std::unique_ptr<Document>& doc = t.doc;
    std::unique_ptr<PreviewSession>&session = t.session, &twin = t.twin;
    const SimulatedBody& buoy = session->world().bodies()[0];
    const double before = buoy.mass.mass;
    const double solid = 150.0 * buoy.volume;
    ASSERT_GT(before - solid, 1.0);  // a shell to thin
    test::executeOrFail(*doc, makeFillAllCommand(*doc, 0, MapChannel::Thickness, 0.5));
    Result<std::vector<std::size_t>> seen = session->followDocument(*doc);
    ASSERT_TRUE(seen.ok()) << seen.error().message;
    EXPECT_EQ(*seen, std::vector<std::size_t>{0});
    // The map's value, one at every pixel.
    const PaintedMap* thickness = doc->map(0, MapChannel::Thickness);
    ASSERT_NE(thickness, nullptr);
    const double half = thickness->values.at(0);
    ASSERT_NEAR(half, 0.5, 1e-4);
    for (float v : thickness->values) ASSERT_EQ(v, thickness->values[0]);
    const double after = session->world().bodies()[0].mass.mass;
    EXPECT_NEAR(after, solid + half * (before - solid), 1e-9 * before);
    // As a preview started from the edited document (the thickness enters the bake's mass).
    auto fresh = sessionOf(*doc);
    ASSERT_TRUE(fresh);
    EXPECT_NEAR(after, fresh->world().bodies()[0].mass.mass, 1e-9 * after);
    const Eigen::Vector3d p0 = session->world().bodies()[0].state.linearMomentum;
    const Eigen::Vector3d q0 = twin->world().bodies()[0].state.linearMomentum;
    EXPECT_LT((p0 - q0).norm(), 1e-12);
    ASSERT_TRUE(session->step().ok() && twin->step().ok());
    const double dt = session->scene().simulation.timeStep;
    const Eigen::Vector3d force = (session->world().bodies()[0].state.linearMomentum - p0) / dt;
    const Eigen::Vector3d twinForce = (twin->world().bodies()[0].state.linearMomentum - q0) / dt;
    EXPECT_NEAR(force.y() - twinForce.y(), (before - after) * 9.81, 0.05 * (before - after) * 9.81);
}

TEST(PreviewSession, PaintedPermeabilityStopsTheFloodingFromTheNextFrame) {
    Twins t = twinsOf("damaged_boat.plim.json", 180);
    ASSERT_TRUE(t);
    std::unique_ptr<Document>& doc = t.doc;
    std::unique_ptr<PreviewSession>&session = t.session, &twin = t.twin;
    const double water = session->world().bodies()[0].water;
    ASSERT_GT(water, 1e-3) << "the boat should be flooding through its stern";
    const RigidBodyState state = session->world().bodies()[0].state;
    // The damage sealed while it floods: permeability 0 everywhere.
    test::executeOrFail(*doc, makeFillAllCommand(*doc, 0, MapChannel::Permeability, 0.0));
    Result<std::vector<std::size_t>> seen = session->followDocument(*doc);
    ASSERT_TRUE(seen.ok()) << seen.error().message;
    EXPECT_EQ(*seen, std::vector<std::size_t>{0});
    // The rebuilt world carries on: the same water, place and momenta, and time.
    EXPECT_NEAR(session->world().bodies()[0].water, water, 1e-12);
    EXPECT_LT((session->world().bodies()[0].state.position - state.position).norm(), 1e-9);
    EXPECT_LT((session->world().bodies()[0].state.linearMomentum - state.linearMomentum).norm(),
              1e-9);
    EXPECT_NEAR(session->world().time(), twin->world().time(), 1e-12);
    // From the next frame on no water enters; the twin keeps flooding.
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(session->step().ok() && twin->step().ok());
    EXPECT_NEAR(session->world().bodies()[0].water, water, 1e-9);
    EXPECT_GT(twin->world().bodies()[0].water, water + 1e-4);
}

/// The water in each node of body 0's running graph, by id.
std::map<std::string, double> nodeWater(const PreviewSession& session) {
    std::map<std::string, double> water;
    const WaterGraphSimulation* graph = session.world().waterGraph(0);
    if (graph) {
        for (const GraphNode& node : graph->graph().nodes) water[node.id] = node.water;
    }
    return water;
}

TEST(PreviewSession, GraphEditsChangeTheFloodingOnTheNextFrameKeepingStateAndWater) {
    // The damaged boat floods through its stern; the stern compartment's pipe to the aft hold
    // carries water on. The pipe removed while it floods: from the next frame on the aft,
    // fore and bow compartments (no damage over them) take no more water, while the twin that
    // did not follow keeps passing it on.
    Twins t = twinsOf("damaged_boat.plim.json", 240);
    ASSERT_TRUE(t);
    std::unique_ptr<Document>& doc = t.doc;
    std::unique_ptr<PreviewSession>&session = t.session, &twin = t.twin;
    const std::map<std::string, double> before = nodeWater(*session);
    ASSERT_EQ(before.size(), 4u);
    ASSERT_GT(before.at("stern"), 1e-3) << "the stern should be flooding";
    const RigidBodyState state = session->world().bodies()[0].state;
    const auto downstream = [](const std::map<std::string, double>& w) {
        return w.at("aft") + w.at("fore") + w.at("bow");
    };
    test::executeOrFail(*doc, makeRemovePipeCommand(*doc, 0, "stern", "aft"));
    Result<std::vector<std::size_t>> seen = session->followDocument(*doc);
    ASSERT_TRUE(seen.ok()) << seen.error().message;
    EXPECT_EQ(*seen, std::vector<std::size_t>{0});
    ASSERT_EQ(session->world().waterGraph(0)->graph().pipes.size(), 2u);
    // The rebuilt world carries on: every node's water, the place, the momenta and the time.
    EXPECT_EQ(nodeWater(*session), before);
    EXPECT_LT((session->world().bodies()[0].state.position - state.position).norm(), 1e-9);
    EXPECT_LT((session->world().bodies()[0].state.linearMomentum - state.linearMomentum).norm(),
              1e-9);
    EXPECT_NEAR(session->world().time(), twin->world().time(), 1e-12);
    for (int i = 0; i < 30; ++i) ASSERT_TRUE(session->step().ok() && twin->step().ok());
    const std::map<std::string, double> cut = nodeWater(*session), joined = nodeWater(*twin);
    EXPECT_NEAR(downstream(cut), downstream(before), 1e-12);
    EXPECT_GT(downstream(joined), downstream(before) + 1e-4);
    EXPECT_GT(cut.at("stern"), joined.at("stern"));  // what no longer leaves the stern

    // A node's water set by hand takes its new value; the others keep theirs.
    NodeEdit edit;
    edit.water = 0.5;
    test::executeOrFail(*doc, makeSetNodeCommand(*doc, 0, "bow", edit));
    seen = session->followDocument(*doc);
    ASSERT_TRUE(seen.ok()) << seen.error().message;
    std::map<std::string, double> expected = cut;
    expected["bow"] = 0.5;
    EXPECT_EQ(nodeWater(*session), expected);
    // Undone: the pipe is back and carries the stern's water on again from the next frame.
    ASSERT_TRUE(doc->undo());
    ASSERT_TRUE(doc->undo());
    seen = session->followDocument(*doc);
    ASSERT_TRUE(seen.ok()) << seen.error().message;
    EXPECT_EQ(session->world().waterGraph(0)->graph().pipes.size(), 3u);
    EXPECT_EQ(nodeWater(*session).at("bow"), 0.0);  // the undone edit's water: the file's
    const double stern = nodeWater(*session).at("stern");
    const double aft = nodeWater(*session).at("aft");
    ASSERT_TRUE(session->step().ok());
    EXPECT_GT(nodeWater(*session).at("aft"), aft);
    EXPECT_GT(stern, 0);
    // Reset starts from the document's graph as edited (all empty: the project's file).
    ASSERT_TRUE(session->reset().ok());
    for (const auto& [id, water] : nodeWater(*session)) EXPECT_EQ(water, 0.0) << id;
}

TEST(PreviewSession, AnInvalidGraphEditIsSaidAndHeldBackUntilValidAgain) {
    // A pipe of the flooding boat's graph turned toward a node that does not exist: the preview
    // says so, naming the body and the node, and runs on with the graph it had (as the twin
    // that did not follow); a later edit that makes the graph valid again is taken.
    Twins t = twinsOf("damaged_boat.plim.json", 120);
    ASSERT_TRUE(t);
    std::unique_ptr<Document>& doc = t.doc;
    std::unique_ptr<PreviewSession>&session = t.session, &twin = t.twin;
    WaterGraph graph = *doc->graph(0);
    ASSERT_EQ(graph.pipes.size(), 3u);
    graph.pipes[0].b = "nowhere";
    test::executeOrFail(*doc, makeReplaceGraphCommand(*doc, 0, graph, "Broken pipe"));
    Result<std::vector<std::size_t>> seen = session->followDocument(*doc);
    ASSERT_FALSE(seen.ok());
    const std::string& said = seen.error().message;
    EXPECT_NE(said.find(session->scene().bodies[0].label), std::string::npos) << said;
    EXPECT_NE(said.find("no node 'nowhere'"), std::string::npos) << said;
    EXPECT_NE(said.find("not simulated"), std::string::npos) << said;
    EXPECT_NE(session->graphProblem(0).find("no node 'nowhere'"), std::string::npos);
    // Asked again (another edit, or none), it still says so: the problem stays until fixed.
    EXPECT_FALSE(session->followDocument(*doc).ok());
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(session->step().ok() && twin->step().ok());
    EXPECT_EQ(nodeWater(*session), nodeWater(*twin));
    EXPECT_EQ(session->world().waterGraph(0)->graph().pipes[0].b, "aft");  // as it ran
    // The scene keeps the graph that runs: a reset (a rebuild from it) works.
    ASSERT_TRUE(session->reset().ok());
    EXPECT_EQ(session->world().waterGraph(0)->graph().pipes.size(), 3u);

    // Valid again (the broken pipe removed): taken from the next frame, the problem gone.
    graph.pipes.erase(graph.pipes.begin());
    test::executeOrFail(*doc, makeReplaceGraphCommand(*doc, 0, graph, "Pipe removed"));
    seen = session->followDocument(*doc);
    ASSERT_TRUE(seen.ok()) << seen.error().message;
    EXPECT_EQ(*seen, std::vector<std::size_t>{0});
    EXPECT_EQ(session->graphProblem(0), "");
    EXPECT_EQ(session->world().waterGraph(0)->graph().pipes.size(), 2u);
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
    EXPECT_EQ(session->world().scene().water.level, 5.0);

    session->setIntegrator(Integrator::RK4);
    ASSERT_TRUE(session->step().ok());
    EXPECT_EQ(session->world().scene().simulation.integrator, Integrator::RK4);
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
    EXPECT_EQ(session->world().scene().water.level, 5.0);  // settings kept
    EXPECT_EQ(session->world().scene().simulation.integrator, Integrator::RK4);
    ASSERT_TRUE(session->step().ok());
}

/// Calls `poll` every few milliseconds until `done` holds or 60 s have passed; whether it held.
template <class Poll, class Done>
bool pollUntil(Poll poll, Done done) {
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!done()) {
        if (std::chrono::steady_clock::now() > give_up) return false;
        poll();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return true;
}

TEST(PreviewSession, NewTextureSizeBakesBehindTheRunningOneWithProgressAndCancel) {
    // 1024^2 froze the editor; paused, the new size only arrived on Play; no
    // progress, no cancel. The request returns at once, the running size keeps stepping, the
    // bake reports progress and Cancel drops it; paused, a finished bake swaps in.
    auto session = makeSession(ballProject(0.0, Eigen::Vector3d(0, -9.81, 0)));
    ASSERT_TRUE(session);
    const double T = session->scene().simulation.timeStep;
    session->requestTextureSize(2048);  // seconds of baking
    EXPECT_TRUE(session->rebuilding());
    EXPECT_EQ(session->rebuildingSize(), 2048);
    EXPECT_EQ(session->textureSize(), 64);  // the running size until the new one is ready
    int frames = 0;
    ASSERT_TRUE(pollUntil(
        [&] {
            ASSERT_TRUE(session->step().ok());
            ++frames;
        },
        [&] { return session->rebuildProgress() > 0.0 || !session->rebuilding(); }));
    ASSERT_TRUE(session->rebuilding()) << "baked 2048^2 before a band was reported";
    EXPECT_GT(session->rebuildProgress(), 0.0);
    EXPECT_LE(session->rebuildProgress(), 1.0);
    EXPECT_EQ(session->textureSize(), 64);
    EXPECT_NEAR(session->world().time(), frames * T, 1e-9);  // stepping all along
    session->cancelRebuild();
    EXPECT_FALSE(session->rebuilding());
    EXPECT_EQ(session->rebuildingSize(), 0);
    for (int i = 0; i < 20; ++i) ASSERT_TRUE(session->update(T).ok());
    EXPECT_EQ(session->textureSize(), 64);  // the cancelled bake never swaps in

    // Paused: a new size swaps in as soon as it is baked, the time standing still. A request
    // made while another bakes replaces it without waiting for it.
    session->pause();
    const double paused = session->world().time();
    const Eigen::Vector3d position = session->world().bodies()[0].state.position;
    session->requestTextureSize(2048);
    session->requestTextureSize(32);
    EXPECT_EQ(session->rebuildingSize(), 32);
    ASSERT_TRUE(pollUntil([&] { ASSERT_TRUE(session->update(T).ok()); },
                          [&] { return !session->rebuilding(); }));
    EXPECT_EQ(session->textureSize(), 32);
    EXPECT_EQ(session->world().bodies()[0].textures.size, 32);
    EXPECT_TRUE(session->rebuildError().empty()) << session->rebuildError();
    EXPECT_EQ(session->world().time(), paused);
    EXPECT_EQ(session->world().bodies()[0].state.position, position);
    EXPECT_FALSE(session->playing());
}

TEST(PreviewSession, FirstHistoryRowHoldsTheFirstFramesBuoyancyNotZero) {
    // The exported CSV started with a submerged volume of 0 at t = 0 (a row
    // written before any step computed a force). The ball (r = 0.5 m) with its centre 0.3 m
    // above the water: a cap of height h = 0.2 m, V = pi h^2 (3 r - h) / 3 = 0.0544 m^3.
    auto session = makeSession(ballProject(0.0, Eigen::Vector3d(0, -9.81, 0)));
    ASSERT_TRUE(session);
    EXPECT_TRUE(session->history().time.empty());
    ASSERT_TRUE(session->step().ok());
    const PreviewHistory& h = session->history();
    ASSERT_EQ(h.time.size(), 1u);
    const double cap = std::numbers::pi * 0.04 * (1.5 - 0.2) / 3.0;
    const PlotSeries* volume = h.find("ball submerged volume");
    ASSERT_TRUE(volume);
    // Within a frame the ball sinks ~1 mm; the faceted sphere and the 64^2 bake a few %.
    EXPECT_NEAR(volume->values[0], cap, 0.06 * cap);
    EXPECT_GT(h.find("ball buoyancy")->values[0], 0.5 * 1000 * 9.81 * cap);
    const fs::path path =
        fs::temp_directory_path() / ("first_row_" + std::to_string(::getpid()) + ".csv");
    ASSERT_TRUE(writeHistoryCsv(h, {"ball submerged volume"}, path).ok());
    std::ifstream in(path);
    std::string header, first;
    std::getline(in, header);
    std::getline(in, first);
    double t = -1, v = -1;
    ASSERT_EQ(std::sscanf(first.c_str(), "%lf,%lf", &t, &v), 2) << first;
    EXPECT_NEAR(t, session->scene().simulation.timeStep, 1e-12);
    EXPECT_EQ(v, volume->values[0]);
    fs::remove(path);
    // A reset starts the history over, again without a row of zeros.
    ASSERT_TRUE(session->reset().ok());
    EXPECT_TRUE(session->history().time.empty());
}

TEST(PreviewSession, HistoryExportsAsCsvThatReadsBack) {
    auto session = makeSession(ballProject(0.0, Eigen::Vector3d(0, -9.81, 0)));
    ASSERT_TRUE(session);
    for (int i = 0; i < 12; ++i) ASSERT_TRUE(session->step().ok());
    const PreviewHistory& h = session->history();
    ASSERT_EQ(h.time.size(), 12u);
    const PlotSeries* volume = h.find("ball submerged volume");
    ASSERT_TRUE(volume);
    ASSERT_TRUE(h.find("ball heel") && h.find("ball trim") && h.find("ball buoyancy"));
    const fs::path path =
        fs::temp_directory_path() / ("preview_" + std::to_string(::getpid()) + ".csv");
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
    Result<Project> project =
        loadProject(fs::path(PLIMSOLL_SOURCE_DIR) / "projects/buoy.plim.json");
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
                  project->bodies[0].textureSize, project->water.level, pose.translation.x(),
                  pose.translation.y(), pose.translation.z(), degrees.x(), degrees.y(), degrees.z(),
                  project->medium.density);
    const test::CommandOutput cli = test::runPlimsoll(args);
    ASSERT_EQ(cli.exitCode, 0) << cli.err;
    const nlohmann::json printed = nlohmann::json::parse(cli.out);
    const double tolerance = 1e-9 * live->exact;
    EXPECT_NEAR(printed["submerged_volume"].get<double>(), live->texture, tolerance);
    EXPECT_NEAR(printed["exact_submerged_volume"].get<double>(), live->exact, tolerance);
    EXPECT_NEAR(printed["submerged_volume_error"].get<double>(), live->error, tolerance);
    EXPECT_NEAR(printed["submerged_volume_relative_error"].get<double>(), live->relativeError,
                1e-9);
    // And the figure means something: a 128^2 bake is within a few percent of exact.
    EXPECT_LT(std::abs(live->relativeError), 0.05);
    std::cout << "buoy 128^2 submerged volume " << live->texture << " m^3, exact " << live->exact
              << ", error " << 100 * live->relativeError << " %\n";
}

TEST(PreviewSession, TheDocumentAsEditedGoesToTheWorldInMemory) {
    const fs::path path = fs::path(PLIMSOLL_SOURCE_DIR) / "projects/buoy.plim.json";
    const fs::path mapFile = fs::path(PLIMSOLL_SOURCE_DIR) / "projects/maps/buoy_ballast.png";
    const std::string mapBefore = test::readFile(mapFile);
    Result<std::unique_ptr<Document>> doc = Document::open(path);
    ASSERT_TRUE(doc.ok()) << doc.error().message;
    // As saved: the scene the project file gives.
    Result<Scene> saved = (*doc)->simulationScene();
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    Result<Project> project = loadProject(path);
    ASSERT_TRUE(project.ok()) << project.error().message;
    const Scene fromDisk = test::sceneOrFail(*project);
    ASSERT_EQ(saved->bodies.size(), 1u);
    ASSERT_EQ(fromDisk.bodies.size(), 1u);
    EXPECT_EQ(saved->bodies[0].textures->position, fromDisk.bodies[0].textures->position);
    EXPECT_EQ(saved->bodies[0].mass->mass, fromDisk.bodies[0].mass->mass);

    // The shell density map painted white all over and not saved: the scene holds the painted
    // map, the mass is the uniform shell's (solid + sigma A), and the file is as it was.
    const PaintedMap* painted = (*doc)->map(0, MapChannel::Density);
    ASSERT_NE(painted, nullptr);
    PaintedMap white = *painted;
    std::fill(white.values.begin(), white.values.end(), 1.0f);
    (*doc)->setMap(0, MapChannel::Density, white);
    Result<Scene> edited = (*doc)->simulationScene();
    ASSERT_TRUE(edited.ok()) << edited.error().message;
    const SceneBody& body = edited->bodies[0];
    ASSERT_TRUE(body.parts.shellDensityMap);
    EXPECT_EQ(body.parts.shellDensityMap->values, white.values);
    const MaterialDesc& m = body.desc.material;
    ASSERT_TRUE(m.density && m.shellSurfaceDensity);
    const double expected =
        *m.density * body.mass->volume + *m.shellSurfaceDensity * body.textures->surfaceArea();
    EXPECT_NEAR(body.mass->mass, expected, 1e-9 * expected);
    EXPECT_GT(body.mass->mass, fromDisk.bodies[0].mass->mass);  // the ballast was partial
    EXPECT_EQ(test::readFile(mapFile), mapBefore);

    Result<std::unique_ptr<PreviewSession>> session =
        PreviewSession::create(std::move(*edited), "reference");
    ASSERT_TRUE(session.ok()) << session.error().message;
    ASSERT_TRUE((*session)->step().ok());
    EXPECT_NEAR((*session)->world().bodies()[0].mass.mass, expected, 1e-9 * expected);
}

TEST(ForceOverlay, WaterlineOfABoxIsItsPerimeterAtTheWaterHeight) {
    const TriangleMesh box = makeBox(Eigen::Vector3d(1.0, 0.6, 2.0));
    // Turned about y (the waterline stays a 1 x 2 rectangle), raised so the water at 0.1 cuts it.
    const Pose pose =
        Pose::fromEulerDegrees(Eigen::Vector3d(3, 0.05, -1), Eigen::Vector3d(0, 35, 0));
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
    EXPECT_LT(
        (weight->to - weight->from - Eigen::Vector3d(0, -0.5 * body.boundingRadius, 0)).norm(),
        1e-9);
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
    body.state.position = body.mass.centerOfMass;       // the sphere's centre on the water
    body.state.orientation = Eigen::Quaterniond::Identity();
    const OverlayImage image = wetTexelOverlay(body, WaterModel::flat(0.0), 0.0);
    ASSERT_EQ(image.width, body.textures.size);
    double wet = 0, total = 0;
    const Eigen::Vector3i wetColour = (kWetColour * 255.0f).array().round().cast<int>();
    for (std::size_t i = 0; i < body.textures.coveredCount(); ++i) {
        const std::size_t texel = body.textures.texelIndex[i];
        const bool isWet =
            image.rgba[4 * texel] == wetColour.x() && image.rgba[4 * texel + 1] == wetColour.y();
        total += body.textures.area[i];
        wet += isWet ? body.textures.area[i] : 0.0;
    }
    // A sphere cut through its centre: half its surface below (texels straddling the line
    // count whole, on either side).
    EXPECT_NEAR(wet / total, 0.5, 0.03);
}

TEST(ForceOverlay, WetTexelsOfALargeTextureAreShownAtTheCappedSize) {
    // A 512^2 bake shown at 256^2 (each shown texel one water test): the same half.
    Project project = ballProject(0.0, Eigen::Vector3d(0, -9.81, 0));
    project.bodies[0].textureSize = 512;
    auto session = makeSession(project);
    ASSERT_TRUE(session);
    SimulatedBody body = session->world().bodies()[0];
    body.state.position = body.mass.centerOfMass;
    body.state.orientation = Eigen::Quaterniond::Identity();
    const OverlayImage image = wetTexelOverlay(body, WaterModel::flat(0.0), 0.0);
    ASSERT_EQ(image.width, kWetOverlayMaxSize);
    ASSERT_EQ(image.rgba.size(), 4u * kWetOverlayMaxSize * kWetOverlayMaxSize);
    const Eigen::Vector3i wetColour = (kWetColour * 255.0f).array().round().cast<int>();
    double wet = 0, total = 0;
    for (std::size_t i = 0; i < body.textures.coveredCount(); ++i) {
        const std::size_t index = body.textures.texelIndex[i];
        const std::size_t texel = (index / 512 / 2) * kWetOverlayMaxSize + (index % 512) / 2;
        total += body.textures.area[i];
        wet += image.rgba[4 * texel] == wetColour.x() ? body.textures.area[i] : 0.0;
    }
    EXPECT_NEAR(wet / total, 0.5, 0.03);

    // The samples found once serve every frame: one entry per shown texel that any covered
    // texel falls in, each the first of them (what the walk over every entry above tested).
    const WetTexelSamples samples = wetTexelSamples(body.textures);
    std::vector<int> firstEntry(kWetOverlayMaxSize * kWetOverlayMaxSize, -1);
    for (std::size_t i = 0; i < body.textures.coveredCount(); ++i) {
        const std::size_t index = body.textures.texelIndex[i];
        const std::size_t texel = (index / 512 / 2) * kWetOverlayMaxSize + (index % 512) / 2;
        if (firstEntry[texel] < 0) firstEntry[texel] = static_cast<int>(i);
    }
    const auto shownTexels = static_cast<std::size_t>(
        std::count_if(firstEntry.begin(), firstEntry.end(), [](int e) { return e >= 0; }));
    ASSERT_EQ(samples.entries.size(), shownTexels);
    ASSERT_EQ(samples.texels.size(), shownTexels);
    for (std::size_t k = 0; k < samples.entries.size(); ++k) {
        EXPECT_EQ(firstEntry[samples.texels[k]], static_cast<int>(samples.entries[k]));
    }
    // Other textures have another key (the preview finds their samples again).
    project.bodies[0].textureSize = 256;
    auto smaller = makeSession(project);
    ASSERT_TRUE(smaller);
    EXPECT_NE(texturesKey(smaller->world().bodies()[0].textures), samples.key);
    EXPECT_EQ(texturesKey(body.textures), samples.key);
}

}  // namespace
}  // namespace test_editor_preview
}  // namespace plimsoll::editor
