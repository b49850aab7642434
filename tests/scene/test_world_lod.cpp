// Level of detail (docs/design.md, "Level of detail"): a body's level ladder is true bakes with
// their stated errors; the World's level follows the policy with hysteresis, and a switch never
// kicks: the acceleration changes by less than the coarser level's stated force error over the
// mass, and energy does not grow.
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/level_ladder.h"
#include "plimsoll/scene/world.h"

#include "plimsoll_eval/levels.hpp"

#include "test_support.h"
#include "world_support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace plimsoll {
namespace test_world_lod {
namespace {

constexpr double kBoxHeight = 0.25;

/// A flat box of half the water's density at `size`^2 with the ladder `levels`, let go 2 cm
/// above its draft at (x, 0, 0).
SceneBody boxBody(int size, std::vector<int> levels, double x = 0.0, double damping = 0.0) {
    BodyDesc body;
    body.name = "box";
    body.mesh = "generated";
    body.textureSize = size;
    body.material.density = 500.0;
    body.position = Eigen::Vector3d(x, 0.02, 0.0);
    body.rotationDegrees = Eigen::Vector3d(3.0, 0.0, 2.0);
    body.linearDamping = damping;
    body.angularDamping = damping;
    if (!levels.empty()) body.lod = LodDesc{std::move(levels)};
    return test::bodyOrFail(body, makeBox(Eigen::Vector3d(1.0, kBoxHeight, 0.8)));
}

Scene sceneOf(std::vector<SceneBody> bodies, WaterModel water = WaterModel::flat(0.0)) {
    Scene scene;
    scene.bodies = std::move(bodies);
    scene.water = std::move(water);
    return scene;
}

WaterModel gentleWaves() {
    WaterModel water;
    water.kind = WaterModel::Kind::Gerstner;
    GerstnerWave wave;
    wave.amplitude = 0.05;
    wave.wavelength = 12.0;
    wave.steepness = 0.3;
    water.waves.push_back(wave);
    return water;
}

TEST(LevelLadder, IsTrueBakesWithTheirStatedErrorsAndKeepsTheMass) {
    const SceneBody plain = boxBody(64, {});
    const SceneBody laddered = boxBody(64, {32, 16, 32});
    EXPECT_FALSE(plain.levels);
    ASSERT_TRUE(laddered.levels);
    const std::vector<BuoyancyLevel>& levels = *laddered.levels;
    ASSERT_EQ(levels.size(), 3u);
    EXPECT_EQ(levels[0].size, 16);
    EXPECT_EQ(levels[1].size, 32);
    EXPECT_EQ(levels[2].size, 64);
    // The finest is the body's own bake; the others are bakes of their own (fewer entries).
    EXPECT_EQ(levels[2].textures, laddered.textures);
    EXPECT_LT(levels[0].textures->coveredCount(), levels[1].textures->coveredCount());
    EXPECT_LT(levels[1].textures->coveredCount(), levels[2].textures->coveredCount());
    // The mass properties are those of texture_size, ladder or not.
    EXPECT_EQ(laddered.mass->mass, plain.mass->mass);
    EXPECT_EQ(laddered.mass->centerOfMass, plain.mass->centerOfMass);
    for (const BuoyancyLevel& level : levels) {
        std::printf("  %d^2: %zu entries, force error %.2e, torque error %.2e, %.2f us\n",
                    level.size, level.textures->coveredCount(), level.forceError, level.torqueError,
                    level.evaluationUs);
        EXPECT_GT(level.forceError, 0.0);
        EXPECT_LT(level.forceError, 0.05);
        EXPECT_GT(level.evaluationUs, 0.0);
    }
    // A level above texture_size is refused, naming it.
    BodyDesc desc = laddered.desc;
    desc.lod = LodDesc{{128}};
    Result<SceneBody> refused = bakeSceneBody(desc, laddered.parts);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("lod level 128"), std::string::npos);
}

TEST(LevelLadder, CoarsenessFollowsTheDistanceWithHysteresis) {
    // Finest within 10 m, one coarser per doubling, at most 3.
    EXPECT_EQ(coarsenessAt(5.0, 10.0, 0.0, 0, 3), 0);
    EXPECT_EQ(coarsenessAt(15.0, 10.0, 0.0, 0, 3), 1);
    EXPECT_EQ(coarsenessAt(30.0, 10.0, 0.0, 0, 3), 2);
    EXPECT_EQ(coarsenessAt(1e6, 10.0, 0.0, 0, 3), 3);
    // With a 15% margin: 11 m is not beyond 10 m by enough; 12 m is; back to finer only at 8.7.
    EXPECT_EQ(coarsenessAt(11.0, 10.0, 0.15, 0, 3), 0);
    EXPECT_EQ(coarsenessAt(12.0, 10.0, 0.15, 0, 3), 1);
    EXPECT_EQ(coarsenessAt(9.0, 10.0, 0.15, 1, 3), 1);
    EXPECT_EQ(coarsenessAt(8.0, 10.0, 0.15, 1, 3), 0);
    EXPECT_EQ(coarsenessAt(45.0, 10.0, 0.15, 1, 3), 2);
}

TEST(LevelLadder, CoarserLevelsTakeHalfTheStepsButNeverFewerThanAStableStep) {
    using plimsoll_eval::stepsAtLevel;
    using plimsoll_eval::strideFor;
    // Four sub-steps at the finest of three levels, two one level down, one at the coarsest.
    EXPECT_EQ(stepsAtLevel(4, 1, 2, 2), 4);
    EXPECT_EQ(stepsAtLevel(4, 1, 1, 2), 2);
    EXPECT_EQ(stepsAtLevel(4, 1, 0, 2), 1);
    EXPECT_EQ(stepsAtLevel(4, 0, 0, 2), 1);  // never none
    EXPECT_EQ(stepsAtLevel(4, 3, 0, 2), 3);  // what a stable step needs
    EXPECT_EQ(stepsAtLevel(4, 1, 0, 40), 1);
    // Strides divide the frame and give at least the steps asked for.
    EXPECT_EQ(strideFor(4, 1), 4);
    EXPECT_EQ(strideFor(4, 2), 2);
    EXPECT_EQ(strideFor(4, 3), 1);
    EXPECT_EQ(strideFor(6, 2), 3);
    EXPECT_EQ(strideFor(6, 4), 1);
    EXPECT_EQ(strideFor(5, 2), 1);  // 5 sub-steps split only into 5
    EXPECT_EQ(strideFor(8, 3), 2);
    for (int frame = 1; frame <= 24; ++frame) {
        for (int steps = 1; steps <= frame; ++steps) {
            const int stride = strideFor(frame, steps);
            EXPECT_EQ(frame % stride, 0) << frame << " " << steps;
            EXPECT_GE(frame / stride, steps) << frame << " " << steps;
        }
    }
}

TEST(WorldLod, ABodyAtACoarserLevelTakesFewerStepsButAStableStepStill) {
    // A box far from the point of interest, at its coarsest level: one step a frame against
    // the project's four; a body whose stable step needs more keeps them.
    const auto evaluationsPerFrame = [](bool fewer, double maxPhaseStep) {
        Scene scene = sceneOf({boxBody(64, {16, 32}, 0.0, 4.0)}, gentleWaves());
        scene.simulation.maxPhaseStep = maxPhaseStep;
        std::unique_ptr<World> world = test::fastWorldOrFail(std::move(scene));
        if (!world) return 0.0;
        LevelPolicy policy;
        policy.kind = LevelPolicy::Kind::distance;
        policy.pointOfInterest = Eigen::Vector3d(1000.0, 0.0, 0.0);
        policy.fewerStepsWhenCoarser = fewer;
        EXPECT_TRUE(world->setLevelPolicy(policy).ok());
        EXPECT_TRUE(world->advanceFrame().ok());  // the switch evaluates both levels once
        const std::size_t before = world->statistics().buoyancyEvaluations;
        for (int f = 0; f < 10; ++f) EXPECT_TRUE(world->advanceFrame().ok());
        EXPECT_EQ(world->bodies()[0].levelSize, 16);
        return (world->statistics().buoyancyEvaluations - before) / 10.0;
    };
    EXPECT_EQ(evaluationsPerFrame(true, 0.5), 1.0);
    EXPECT_EQ(evaluationsPerFrame(false, 0.5), 4.0);
    // maxPhaseStep 0.05: the box's stiffness needs more than the project's 4 steps a frame,
    // and it takes them at the coarsest level too.
    const double stiff = evaluationsPerFrame(false, 0.05);
    EXPECT_GT(stiff, 4.0);
    EXPECT_EQ(evaluationsPerFrame(true, 0.05), stiff);
}

TEST(WorldLod, TheLevelFollowsTheDistancePolicyAndDoesNotFlipWithinTheMargin) {
    std::unique_ptr<World> world =
        test::fastWorldOrFail(sceneOf({boxBody(64, {16, 32}, 9.0, 4.0)}));
    ASSERT_TRUE(world);
    EXPECT_EQ(world->bodies()[0].levelSize, 64);  // the finest until a policy says otherwise
    LevelPolicy policy;
    policy.kind = LevelPolicy::Kind::distance;
    policy.nearDistance = 10.0;
    policy.margin = 0.15;
    policy.holdFrames = 0;
    ASSERT_TRUE(world->setLevelPolicy(policy).ok());
    const auto moveTo = [&](double x) {
        RigidBodyState state = world->bodies()[0].state;
        state.position.x() = x;
        ASSERT_TRUE(world->setBodyState(0, state).ok());
        ASSERT_TRUE(world->advanceFrame().ok());
    };
    // Back and forth across the 10 m boundary by less than the margin: no switch.
    for (int i = 0; i < 20; ++i) moveTo(i % 2 ? 11.0 : 9.0);
    EXPECT_EQ(world->bodies()[0].levelSize, 64);
    EXPECT_EQ(world->statistics().levelSwitches, 0u);
    moveTo(12.0);  // beyond it by more: one level coarser
    EXPECT_EQ(world->bodies()[0].levelSize, 32);
    for (int i = 0; i < 20; ++i) moveTo(i % 2 ? 9.0 : 11.0);
    EXPECT_EQ(world->bodies()[0].levelSize, 32);
    EXPECT_EQ(world->statistics().levelSwitches, 1u);
    moveTo(8.0);
    EXPECT_EQ(world->bodies()[0].levelSize, 64);
    moveTo(1000.0);  // far: the coarsest the ladder has
    EXPECT_EQ(world->bodies()[0].levelSize, 16);
    // At most one switch every holdFrames frames.
    policy.holdFrames = 30;
    ASSERT_TRUE(world->setLevelPolicy(policy).ok());
    moveTo(5.0);  // the last switch was a frame ago: held
    EXPECT_EQ(world->bodies()[0].levelSize, 16);
    for (int i = 0; i < 30; ++i) moveTo(5.0);
    EXPECT_EQ(world->bodies()[0].levelSize, 64);
    const std::size_t switches = world->statistics().levelSwitches;
    moveTo(1000.0);
    EXPECT_EQ(world->statistics().levelSwitches, switches);
    EXPECT_EQ(world->bodies()[0].levelSize, 64);
    // A bad policy is refused.
    policy.blendFrames = 0;
    EXPECT_FALSE(world->setLevelPolicy(policy).ok());
}

TEST(WorldLod, TheBudgetPolicyGivesTheNearestBodiesTheFinestLevelItPaysFor) {
    // One bake shared: the same measured cost per level for every body.
    const SceneBody box = boxBody(64, {16, 32}, 0.0, 4.0);
    std::vector<SceneBody> bodies(4, box);
    for (int i = 0; i < 4; ++i) bodies[i].desc.position.x() = 3.0 * i;
    std::unique_ptr<World> world = test::fastWorldOrFail(sceneOf(std::move(bodies)));
    ASSERT_TRUE(world);
    const std::vector<BuoyancyLevel>& levels = *world->levels(0);
    const int subSteps = world->scene().simulation.subSteps;
    // A level's cost a frame is its cost per evaluation times the steps it takes: the box's
    // stable step needs one a frame, so the coarsest takes one, the finest the project's four.
    const auto frameCost = [&](int level) {
        const int steps = plimsoll_eval::stepsAtLevel(subSteps, 1, level, 2);
        return levels[static_cast<std::size_t>(level)].evaluationUs *
               (subSteps / plimsoll_eval::strideFor(subSteps, steps));
    };
    EXPECT_EQ(frameCost(0), levels[0].evaluationUs);
    EXPECT_EQ(frameCost(2), subSteps * levels[2].evaluationUs);
    LevelPolicy policy;
    policy.kind = LevelPolicy::Kind::budget;
    // All at the coarsest, and the finest for one body (the nearest, body 0).
    policy.budgetUs = (4 * frameCost(0) + (frameCost(2) - frameCost(0))) * 1.001;
    ASSERT_TRUE(world->setLevelPolicy(policy).ok());
    ASSERT_TRUE(world->advanceFrame().ok());
    EXPECT_EQ(world->bodies()[0].levelSize, 64);
    for (std::size_t i = 1; i < 4; ++i) EXPECT_LE(world->bodies()[i].levelSize, 32) << i;
    EXPECT_EQ(world->bodies()[3].levelSize, 16);
}

/// Largest change of the linear acceleration from frame to frame (m/s^2) from kSettled (3 s,
/// the drop's transient over) to `frames`, for a body whose importance toggles between 1 and
/// 1/4 every second when `switching`.
constexpr int kSettled = 180;
struct Jumps {
    double largest = 0;
    std::size_t switches = 0;
};
Jumps accelerationJumps(WaterModel water, bool switching, int frames, double& bound) {
    std::unique_ptr<World> world =
        test::fastWorldOrFail(sceneOf({boxBody(64, {16}, 0.0, 1.0)}, std::move(water)));
    if (!world) return {};
    const std::vector<BuoyancyLevel>& levels = *world->levels(0);
    const SimulatedBody& body = world->bodies()[0];
    bound = levels.front().forceError * 1000.0 * 9.81 * body.volume / body.mass.mass;
    LevelPolicy policy;
    policy.kind = LevelPolicy::Kind::importance;
    policy.holdFrames = 0;
    const double dt = world->scene().simulation.timeStep;
    Eigen::Vector3d lastVelocity = linearVelocity(body.state, body.mass);
    Eigen::Vector3d lastAcceleration = Eigen::Vector3d::Zero();
    Jumps jumps;
    for (int f = 0; f < frames; ++f) {
        if (switching && f % 60 == 0) {
            policy.importance = {(f / 60) % 2 ? 1.0 : 0.25};
            EXPECT_TRUE(world->setLevelPolicy(policy).ok());
        }
        EXPECT_TRUE(world->advanceFrame().ok());
        const Eigen::Vector3d velocity = linearVelocity(body.state, body.mass);
        const Eigen::Vector3d acceleration = (velocity - lastVelocity) / dt;
        if (f >= kSettled)
            jumps.largest = std::max(jumps.largest, (acceleration - lastAcceleration).norm());
        lastVelocity = velocity;
        lastAcceleration = acceleration;
    }
    jumps.switches = world->statistics().levelSwitches;
    return jumps;
}

TEST(WorldLod, SwitchingEverySecondOnWavesNeverJumpsBeyondTheCoarserLevelsError) {
    // 10 s after the box settled into the waves' motion (from 3 s on): the frame-to-frame
    // change of the acceleration with a switch every second against the same run without.
    for (const bool onWaves : {false, true}) {
        SCOPED_TRACE(onWaves ? "on waves" : "on flat water");
        const WaterModel water = onWaves ? gentleWaves() : WaterModel::flat(0.0);
        double bound = 0;
        const Jumps fixed = accelerationJumps(water, false, 780, bound);
        const Jumps switching = accelerationJumps(water, true, 780, bound);
        EXPECT_GE(switching.switches, 12u);
        std::printf(
            "  %s: largest jump %.3e m/s^2 switching, %.3e fixed; bound (16^2 force "
            "error / mass) %.3e\n",
            onWaves ? "waves" : "flat", switching.largest, fixed.largest, bound);
        EXPECT_LE(switching.largest, fixed.largest + bound);
    }
}

TEST(WorldLod, EnergyDoesNotGrowOnFlatWaterWithoutDragWhileSwitching) {
    BodyDesc desc;
    desc.name = "sphere";
    desc.mesh = "generated";
    desc.textureSize = 64;
    desc.material.density = 500.0;
    desc.rotationDegrees = Eigen::Vector3d(10, 0, 5);
    desc.position = Eigen::Vector3d(0, 0.2, 0);
    desc.dragCoefficient = 0;
    desc.linearDamping = desc.angularDamping = 0;
    desc.lod = LodDesc{{16, 32}};
    Scene scene = sceneOf({test::bodyOrFail(desc, makeUvSphere(0.5, 16, 8))});
    scene.simulation.maxPhaseStep = 0.025;  // the energy tests' step (test_stability.cpp)
    std::unique_ptr<World> world = test::fastWorldOrFail(std::move(scene));
    ASSERT_TRUE(world);
    LevelPolicy policy;
    policy.kind = LevelPolicy::Kind::importance;
    policy.holdFrames = 0;
    const SimulatedBody& b = world->bodies()[0];
    const double scale = std::max(b.mass.mass, 1000.0 * b.volume) * 9.81 * 0.5;
    const double initial = world->mechanicalEnergy(0);
    double worst = -1e300;
    for (int f = 0; f < 1200; ++f) {
        if (f % 60 == 0) {
            policy.importance = {(f / 60) % 3 == 0 ? 1.0 : (f / 60) % 3 == 1 ? 0.5 : 0.25};
            ASSERT_TRUE(world->setLevelPolicy(policy).ok());
        }
        ASSERT_TRUE(world->advanceFrame().ok());
        worst = std::max(worst, world->mechanicalEnergy(0) - initial);
    }
    EXPECT_GE(world->statistics().levelSwitches, 15u);
    std::printf("  worst energy rise %.2e of scale\n", worst / (std::abs(initial) + scale));
    EXPECT_LE(worst, 0.01 * (std::abs(initial) + scale));
}

}  // namespace
}  // namespace test_world_lod
}  // namespace plimsoll
