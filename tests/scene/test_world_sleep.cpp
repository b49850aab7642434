// Sleeping bodies (docs/design.md, "Sleeping bodies"): a body at rest on calm water falls
// asleep where Archimedes puts it and costs no evaluation; each waking rule wakes it.
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/world.h"

#include "test_support.h"
#include "world_support.h"

#include <Eigen/Geometry>

#include <cmath>

namespace plimsoll {
namespace test_world_sleep {
namespace {

constexpr double kBoxHeight = 0.25;
constexpr double kDensity = 500.0;  // floats at half its height: 0.125 m

/// A flat box of half the water's density let go 2 cm above its draft, damped so that it
/// comes to rest within a few seconds.
Scene restingBox(std::size_t count = 1) {
    Scene scene;
    for (std::size_t i = 0; i < count; ++i) {
        BodyDesc body;
        body.name = "box" + std::to_string(i);
        body.mesh = "generated";
        body.textureSize = 32;
        body.material.density = kDensity;
        body.position = Eigen::Vector3d(3.0 * static_cast<double>(i), 0.02, 0.0);
        body.linearDamping = 4.0;
        body.angularDamping = 4.0;
        scene.bodies.push_back(
            test::bodyOrFail(body, makeBox(Eigen::Vector3d(1.0, kBoxHeight, 0.8))));
    }
    scene.medium.density = 1000.0;
    scene.water = WaterModel::flat(0.0);
    return scene;
}

/// Frames until body 0 sleeps (-1: not within `limit` frames).
int framesToSleep(World& world, int limit, std::size_t body = 0) {
    for (int f = 0; f < limit; ++f) {
        EXPECT_TRUE(world.advanceFrame().ok());
        if (world.bodies()[body].asleep) return f + 1;
    }
    return -1;
}

/// Depth of the box's bottom below the water (its centre of mass is at mid height).
double draftOf(const SimulatedBody& body) { return kBoxHeight / 2 - body.state.position.y(); }

/// One 10 m wave; `steepness` 0 is a sine wave, whose water moves A w, where a Gerstner wave's
/// moves Q / k w whatever its amplitude.
WaterModel waves(double amplitude, double steepness) {
    WaterModel water;
    water.kind = WaterModel::Kind::Gerstner;
    GerstnerWave wave;
    wave.amplitude = amplitude;
    wave.wavelength = 10.0;
    wave.steepness = steepness;
    water.waves.push_back(wave);
    return water;
}

TEST(WorldSleep, ABodyAtRestOnFlatWaterSleepsAtItsDraftAndCostsNoEvaluation) {
    std::unique_ptr<World> world = test::fastWorldOrFail(restingBox());
    ASSERT_TRUE(world);
    const int frames = framesToSleep(*world, 1200);
    ASSERT_GT(frames, 0) << "the box did not fall asleep in 20 s";
    // Not before it rested the full rest time.
    EXPECT_GE(frames * world->scene().simulation.timeStep,
              world->scene().simulation.sleep.restTime);
    const SimulatedBody& body = world->bodies()[0];
    // Asleep within linear_acceleration / w^2 of Archimedes' draft (heave w = sqrt(g / draft)
    // = 8.9 rad/s: 0.13 mm), the texture's own error (0.1 mm at 32^2) beside it.
    EXPECT_NEAR(draftOf(body), kBoxHeight * kDensity / 1000.0, 4e-4);
    EXPECT_EQ(body.state.linearMomentum.norm(), 0.0);
    EXPECT_EQ(world->statistics().fallsAsleep, 1u);

    const std::size_t evaluations = world->statistics().buoyancyEvaluations;
    const Eigen::Vector3d at = body.state.position;
    for (int f = 0; f < 120; ++f) ASSERT_TRUE(world->advanceFrame().ok());
    EXPECT_EQ(world->statistics().buoyancyEvaluations, evaluations);
    EXPECT_EQ(world->statistics().sleepingBodyFrames, 120u);
    EXPECT_EQ(world->bodies()[0].state.position, at);
    EXPECT_TRUE(world->bodies()[0].asleep);
}

TEST(WorldSleep, SleepingOffComputesEveryFrame) {
    Scene scene = restingBox();
    scene.simulation.sleep.enabled = false;
    std::unique_ptr<World> world = test::fastWorldOrFail(std::move(scene));
    ASSERT_TRUE(world);
    EXPECT_EQ(framesToSleep(*world, 600), -1);
    EXPECT_EQ(world->statistics().buoyancyEvaluations,
              world->statistics().steps);  // one body, one evaluation a step
}

TEST(WorldSleep, AWaveArrivingWakesItAndRippleDoesNot) {
    std::unique_ptr<World> world = test::fastWorldOrFail(restingBox());
    ASSERT_TRUE(world);
    ASSERT_GT(framesToSleep(*world, 1200), 0);
    // A ripple of 0.3 mm: its surface moves at A w = 0.3 mm * 2.5 rad/s < 5 mm/s: calm. The new
    // water wakes the body; it sleeps again.
    world->setWater(waves(0.0003, 0.0));
    EXPECT_FALSE(world->bodies()[0].asleep);
    ASSERT_GT(framesToSleep(*world, 1200), 0);
    const std::size_t evaluations = world->statistics().buoyancyEvaluations;
    const std::size_t wakeUps = world->statistics().wakeUps;
    for (int f = 0; f < 60; ++f) ASSERT_TRUE(world->advanceFrame().ok());
    EXPECT_TRUE(world->bodies()[0].asleep);
    EXPECT_EQ(world->statistics().buoyancyEvaluations, evaluations);
    // A 10 cm swell: the body wakes, is evaluated again and rides it.
    world->setWater(waves(0.1, 0.3));
    const double y = world->bodies()[0].state.position.y();
    for (int f = 0; f < 60; ++f) ASSERT_TRUE(world->advanceFrame().ok());
    EXPECT_FALSE(world->bodies()[0].asleep);
    EXPECT_GT(world->statistics().wakeUps, wakeUps);
    EXPECT_GT(world->statistics().buoyancyEvaluations, evaluations + 60);
    EXPECT_GT(std::abs(world->bodies()[0].state.position.y() - y), 0.01);
}

TEST(WorldSleep, ASteepWaveOfSmallHeightIsNotCalm) {
    // A 0.3 mm Gerstner wave of steepness 0.3 moves its water Q / k w = 1.2 m/s sideways: it
    // pushes the box about, and the box never sleeps on it.
    Scene scene = restingBox();
    scene.water = waves(0.0003, 0.3);
    std::unique_ptr<World> world = test::fastWorldOrFail(std::move(scene));
    ASSERT_TRUE(world);
    EXPECT_EQ(framesToSleep(*world, 600), -1);
}

TEST(WorldSleep, TheWaterChangingUnderASleepingBodyWakesIt) {
    std::unique_ptr<World> world = test::fastWorldOrFail(restingBox());
    ASSERT_TRUE(world);
    ASSERT_GT(framesToSleep(*world, 1200), 0);
    // The level rises 5 cm (a tide, a lock filling): more than wake_height. setWater wakes every
    // body anyway; the body then rises with the water and sleeps at the new draft.
    world->setWater(WaterModel::flat(0.05));
    ASSERT_GT(framesToSleep(*world, 1200), 0);
    EXPECT_NEAR(draftOf(world->bodies()[0]) + 0.05, kBoxHeight * kDensity / 1000.0, 4e-4);
}

TEST(WorldSleep, AForceWakesItAndAZeroForceLetsItSleep) {
    std::unique_ptr<World> world = test::fastWorldOrFail(restingBox());
    ASSERT_TRUE(world);
    // A game's hook that pushes only when asked: zero, the body sleeps as without it.
    bool push = false;
    ASSERT_TRUE(world
                    ->setExternalForce(0,
                                       [&](const SimulatedBody&, const RigidBodyState&) {
                                           return push ? Wrench{Eigen::Vector3d(50.0, 0, 0),
                                                                Eigen::Vector3d::Zero()}
                                                       : Wrench{};
                                       })
                    .ok());
    ASSERT_GT(framesToSleep(*world, 1200), 0);
    const double x = world->bodies()[0].state.position.x();
    push = true;
    ASSERT_TRUE(world->advanceFrame().ok());
    EXPECT_FALSE(world->bodies()[0].asleep);
    for (int f = 0; f < 30; ++f) ASSERT_TRUE(world->advanceFrame().ok());
    EXPECT_GT(world->bodies()[0].state.position.x() - x, 0.005);
    // A pushed body never sleeps, however slowly the push moves it against the drag.
    EXPECT_EQ(framesToSleep(*world, 300), -1);
    // And World::wake wakes it whatever the reason.
    push = false;
    ASSERT_GT(framesToSleep(*world, 1200), 0);
    ASSERT_TRUE(world->wake(0).ok());
    EXPECT_FALSE(world->bodies()[0].asleep);
    EXPECT_FALSE(world->wake(7).ok());
}

TEST(WorldSleep, ABodyStaysAwakeWhileItsWaterGraphMovesWater) {
    // Loose thresholds (a metre a second) leave only the flooding rule to keep the body awake:
    // the plush toy soaking up water through its skin stays awake while water comes in, where
    // the same toy sealed sleeps after the rest time.
    Result<Project> loaded =
        loadProject(std::filesystem::path(PLIMSOLL_SOURCE_DIR) / "projects" / "plush.plim.json");
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    Project project = *loaded;
    project.simulation.sleep.linearSpeed = 1.0;
    project.simulation.sleep.angularSpeed = 1.0;
    project.simulation.sleep.linearAcceleration = 100.0;
    project.simulation.sleep.angularAcceleration = 100.0;
    std::unique_ptr<World> flooding = test::fastWorldOrFail(test::sceneOrFail(project));
    ASSERT_TRUE(flooding);
    double before = flooding->bodies()[0].water;
    int moving = 0;
    for (int f = 0; f < 240; ++f) {
        ASSERT_TRUE(flooding->advanceFrame().ok());
        const double water = flooding->bodies()[0].water;
        if (water != before) {
            ++moving;
            EXPECT_FALSE(flooding->bodies()[0].asleep) << "frame " << f;
        }
        before = water;
    }
    EXPECT_GT(moving, 200);  // water came in on (nearly) every frame of these 4 s

    project.bodies[0].waterGraph.reset();
    std::unique_ptr<World> sealed = test::fastWorldOrFail(test::sceneOrFail(project));
    ASSERT_TRUE(sealed);
    const int frames = framesToSleep(*sealed, 240);
    EXPECT_GT(frames, 0);
}

TEST(WorldSleep, ThousandSleepingBodiesCostNoEvaluation) {
    // What the bench's 1000 resting bodies measure, counted: once asleep, a frame of many bodies
    // evaluates none of them.
    std::unique_ptr<World> world = test::fastWorldOrFail(restingBox(20));
    ASSERT_TRUE(world);
    bool all = false;
    for (int f = 0; f < 1200 && !all; ++f) {
        ASSERT_TRUE(world->advanceFrame().ok());
        all = std::all_of(world->bodies().begin(), world->bodies().end(),
                          [](const SimulatedBody& b) { return b.asleep; });
    }
    ASSERT_TRUE(all);
    const std::size_t evaluations = world->statistics().buoyancyEvaluations;
    for (int f = 0; f < 30; ++f) ASSERT_TRUE(world->advanceFrame().ok());
    EXPECT_EQ(world->statistics().buoyancyEvaluations, evaluations);
}

}  // namespace
}  // namespace test_world_sleep
}  // namespace plimsoll
