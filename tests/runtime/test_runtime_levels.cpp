// Level of detail in the runtime (docs/bundle.md "levels", runtime.hpp LevelPolicy): a bundle
// exported with a level ladder loads every level with its stated error, and each level's forces
// stay within that error of the exact clip; an older bundle has one level; with the finest level
// the Simulation steps bit for bit as without a ladder; a body switching level every second
// never jumps in acceleration beyond the coarser level's stated force error over the mass; a
// snapshot taken inside a blend continues bit for bit; the C API sets the policy.
#include "test_support.h"
#include "world_support.h"

#include "plimsoll/export/bundle.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/physics/pose.h"
#include "plimsoll/project/project.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/geometry/box.h"
#include "plimsoll/scene/level_ladder.h"
#include "plimsoll/scene/world.h"

#include "plimsoll_runtime.h"
#include "plimsoll_runtime/runtime.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <vector>

namespace plimsoll {
namespace test_runtime_levels {
namespace {

namespace fs = std::filesystem;
namespace rt = plimsoll_runtime;

constexpr double kRhoG = 1000.0 * 9.81;

Eigen::Vector3d eigen(const rt::Vec3& v) { return {v.x, v.y, v.z}; }

/// A flat box (1 x 0.25 x 0.8 m) of half the water's density at 64^2 with the ladder 16, 32, 64,
/// let go 2 cm above its draft with a small heel, damped so that it settles; exported on flat
/// water ("flat") and on gentle waves ("waves"), and the flat bundle once more with its manifest
/// stripped of the ladder as a 1.5 exporter wrote it ("older").
class RuntimeLevels : public testing::Test {
protected:
    static void SetUpTestSuite() {
        root_ = new fs::path(test::scratchFolder("runtime_levels"));
        mesh_ = new TriangleMesh(makeBox(Eigen::Vector3d(1.0, 0.25, 0.8)));
        ASSERT_TRUE(writeObj(*mesh_, *root_ / "box.obj").ok());
        project_ = new Project();
        Project& p = *project_;
        p.name = "laddered_box";
        p.folder = *root_;
        BodyDesc body;
        body.name = "box";
        body.mesh = "box.obj";
        body.textureSize = 64;
        body.material.density = 500;
        body.position = Eigen::Vector3d(0, 0.02, 0);
        body.rotationDegrees = Eigen::Vector3d(3, 0, 2);
        body.linearDamping = body.angularDamping = 1.0;
        body.lod = LodDesc{{16, 32}};
        p.bodies.push_back(body);
        Result<BundleReport> flat = writeBodyBundle(p, 0, *root_ / "flat");
        ASSERT_TRUE(flat.ok()) << flat.error().message;
        Result<BundleReport> onWaves = writeBodyBundle(wavy(p), 0, *root_ / "waves");
        ASSERT_TRUE(onWaves.ok()) << onWaves.error().message;
        // The manifest is not among the files it lists: only it changes.
        fs::copy(*root_ / "flat", *root_ / "older", fs::copy_options::recursive);
        const fs::path manifest = *root_ / "older" / "manifest.json";
        nlohmann::json m = nlohmann::json::parse(test::readFile(manifest));
        m.erase("levels");
        m["schema_minor"] = 5;
        std::ofstream(manifest) << m.dump(2);
    }
    /// `p` on gentle waves.
    static Project wavy(Project p) {
        p.water.kind = WaterModel::Kind::Gerstner;
        GerstnerWave wave;
        wave.amplitude = 0.05;
        wave.wavelength = 12.0;
        wave.steepness = 0.3;
        p.water.waves.push_back(wave);
        return p;
    }
    static void TearDownTestSuite() {
        fs::remove_all(*root_);
        delete root_;
        delete project_;
        delete mesh_;
    }
    static std::unique_ptr<rt::Bundle> load(const std::string& name) {
        std::string error;
        std::unique_ptr<rt::Bundle> bundle = rt::loadBundle((*root_ / name).string(), error);
        EXPECT_TRUE(bundle) << error;
        return bundle;
    }
    static std::unique_ptr<rt::Simulation> simulate(const rt::Bundle& bundle) {
        std::string error;
        std::unique_ptr<rt::Simulation> s = rt::Simulation::create(bundle, error);
        EXPECT_TRUE(s) << error;
        return s;
    }
    static fs::path* root_;
    static Project* project_;
    static TriangleMesh* mesh_;
};
fs::path* RuntimeLevels::root_ = nullptr;
Project* RuntimeLevels::project_ = nullptr;
TriangleMesh* RuntimeLevels::mesh_ = nullptr;

TEST_F(RuntimeLevels, EveryLevelLoadsWithItsStatedErrorAndStaysWithinItOfTheExactClip) {
    Result<SceneBody> body = loadSceneBody(*project_, 0, {});
    ASSERT_TRUE(body.ok()) << body.error().message;
    ASSERT_TRUE(body->levels);
    const std::vector<BuoyancyLevel>& ladder = *body->levels;
    std::unique_ptr<rt::Bundle> bundle = load("flat");
    ASSERT_TRUE(bundle);
    EXPECT_EQ(bundle->schemaMinor(), 6);
    const std::vector<rt::BundleLevel>& levels = bundle->levels();
    ASSERT_EQ(levels.size(), 3u);
    const Eigen::Vector3d c = body->mass->centerOfMass;
    const double volume = bundle->mass().volume;
    for (std::size_t k = 0; k < 3; ++k) {
        SCOPED_TRACE(k);
        EXPECT_EQ(levels[k].size, ladder[k].size);
        EXPECT_EQ(levels[k].samples, ladder[k].textures->coveredCount());
        EXPECT_EQ(levels[k].forceError, ladder[k].forceError);
        EXPECT_EQ(levels[k].torqueError, ladder[k].torqueError);
        double worst = 0;
        // The poses the stated error was measured over; the exact clip of the mesh as reference.
        for (const LevelPose& pose : levelErrorPoses(*mesh_, c)) {
            BodyFrame frame;
            frame.pose.rotation = pose.rotation;
            frame.pose.translation = -(pose.rotation * c);
            frame.centerOfMass = c;
            const BuoyancyResult exact =
                evaluateBuoyancyExact(*mesh_, frame, pose.waterLevel, FluidSettings{});
            rt::Pose p;
            const Eigen::Quaterniond q(pose.rotation);
            p.orientation = {q.w(), q.x(), q.y(), q.z()};
            p.position = {frame.pose.translation.x(), frame.pose.translation.y(),
                          frame.pose.translation.z()};
            rt::Water water;
            water.level = pose.waterLevel;
            rt::Fluid fluid;
            fluid.dragCoefficient = 0;
            const rt::Forces f = bundle->evaluateLevel(k, p, {}, water, fluid);
            const Eigen::Vector3d force(f.force.x, f.force.y, f.force.z);
            worst = std::max(worst, (force - exact.force).norm() / (kRhoG * volume));
        }
        std::printf("  %d^2: %zu samples, stated force error %.2e, runtime's %.2e\n",
                    levels[k].size, levels[k].samples, levels[k].forceError, worst);
        // The fast path adds its float rounding to the bake's error.
        EXPECT_LE(worst, levels[k].forceError + 1e-5);
        if (k < 2) EXPECT_GT(levels[k].forceError, levels[2].forceError);
    }
}

TEST_F(RuntimeLevels, AnOlderBundleHasOneLevel) {
    std::unique_ptr<rt::Bundle> bundle = load("older");
    ASSERT_TRUE(bundle);
    ASSERT_EQ(bundle->levels().size(), 1u);
    EXPECT_EQ(bundle->levels()[0].size, 64);
    EXPECT_EQ(bundle->levels()[0].samples, bundle->samples().size());
    EXPECT_EQ(bundle->levels()[0].forceError, 0.0);
}

TEST_F(RuntimeLevels, AManifestWhoseLevelsDoNotFitTheBodyIsRefused) {
    const fs::path folder = *root_ / "bad_levels";
    fs::remove_all(folder);
    fs::copy(*root_ / "flat", folder, fs::copy_options::recursive);
    const fs::path manifest = folder / "manifest.json";
    const nlohmann::json good = nlohmann::json::parse(test::readFile(manifest));
    const auto refused = [&](const std::function<void(nlohmann::json&)>& change) {
        nlohmann::json m = good;
        change(m);
        std::ofstream(manifest) << m.dump(2);
        std::string error;
        EXPECT_FALSE(rt::loadBundle(folder.string(), error));
        return error;
    };
    EXPECT_NE(
        refused([](nlohmann::json& m) { m["levels"][1]["size"] = 8; }).find("$.levels[1].size"),
        std::string::npos);
    EXPECT_NE(refused([](nlohmann::json& m) {
                  m["levels"][2]["samples"] = "levels/16/samples.exr";
              }).find("the finest level must be samples.exr"),
              std::string::npos);
    EXPECT_NE(refused([](nlohmann::json& m) {
                  m["levels"][0]["samples"] = "../flat/samples.exr";
              }).find("leaves the bundle"),
              std::string::npos);
    EXPECT_NE(
        refused([](nlohmann::json& m) { m["levels"][0]["force_error"] = -1; }).find("$.levels[0]"),
        std::string::npos);
}

TEST_F(RuntimeLevels, WithTheFinestLevelTheSimulationStepsBitForBitAsWithoutALadder) {
    std::unique_ptr<rt::Bundle> laddered = load("flat"), older = load("older");
    ASSERT_TRUE(laddered && older);
    std::unique_ptr<rt::Simulation> a = simulate(*laddered), b = simulate(*older);
    ASSERT_TRUE(a && b);
    const rt::Water water = laddered->world().water.water();
    std::string error;
    for (int f = 0; f < 240; ++f) {
        ASSERT_TRUE(a->advanceFrame(water, error)) << error;
        ASSERT_TRUE(b->advanceFrame(water, error)) << error;
    }
    EXPECT_EQ(a->level(), 2u);
    EXPECT_EQ(a->levelSwitches(), 0u);
    EXPECT_EQ(std::memcmp(&a->centerOfMass(), &b->centerOfMass(), sizeof(rt::Vec3)), 0);
    EXPECT_EQ(std::memcmp(&a->orientation(), &b->orientation(), sizeof(rt::Quat)), 0);
    const rt::Vec3 va = a->linearVelocity(), vb = b->linearVelocity();
    EXPECT_EQ(std::memcmp(&va, &vb, sizeof(rt::Vec3)), 0);
}

/// The largest frame-to-frame change of the acceleration after the body settled (3 s), with the
/// level switched between the coarsest and the finest every second when `switching`.
struct Jumps {
    double largest = 0;
    std::size_t switches = 0;
};
Jumps accelerationJumps(const rt::Bundle& bundle, bool switching, int frames) {
    std::string error;
    std::unique_ptr<rt::Simulation> s = rt::Simulation::create(bundle, error);
    EXPECT_TRUE(s) << error;
    if (!s) return {};
    const rt::Water water = bundle.world().water.water();
    rt::LevelPolicy policy;
    policy.kind = rt::LevelPolicy::Kind::fixed;
    policy.holdFrames = 0;
    const double dt = s->frameTime();
    Eigen::Vector3d lastVelocity = eigen(s->linearVelocity()),
                    lastAcceleration = Eigen::Vector3d::Zero();
    Jumps jumps;
    for (int f = 0; f < frames; ++f) {
        if (switching && f % 60 == 0) {
            policy.level = (f / 60) % 2 ? 2 : 0;
            EXPECT_TRUE(s->setLevelPolicy(policy, error)) << error;
        }
        EXPECT_TRUE(s->advanceFrame(water, error)) << error;
        const Eigen::Vector3d velocity = eigen(s->linearVelocity());
        const Eigen::Vector3d acceleration = (velocity - lastVelocity) / dt;
        if (f >= 180)
            jumps.largest = std::max(jumps.largest, (acceleration - lastAcceleration).norm());
        lastVelocity = velocity;
        lastAcceleration = acceleration;
    }
    jumps.switches = s->levelSwitches();
    return jumps;
}

TEST_F(RuntimeLevels, SwitchingEverySecondNeverJumpsBeyondTheCoarserLevelsError) {
    for (const char* name : {"flat", "waves"}) {
        SCOPED_TRACE(name);
        std::unique_ptr<rt::Bundle> bundle = load(name);
        ASSERT_TRUE(bundle);
        const rt::BundleLevel& coarsest = bundle->levels().front();
        const double bound =
            coarsest.forceError * kRhoG * bundle->mass().volume / bundle->mass().mass;
        const Jumps fixed = accelerationJumps(*bundle, false, 780);
        const Jumps switching = accelerationJumps(*bundle, true, 780);
        EXPECT_EQ(fixed.switches, 0u);
        EXPECT_GE(switching.switches, 12u);
        std::printf(
            "  %s: largest jump %.3e m/s^2 switching, %.3e fixed; bound (%d^2 force error / mass) "
            "%.3e\n",
            name, switching.largest, fixed.largest, coarsest.size, bound);
        EXPECT_LE(switching.largest, fixed.largest + bound);
    }
}

TEST_F(RuntimeLevels, TheDistancePolicyCoarsensWithHysteresisAndASnapshotInsideABlendContinues) {
    std::unique_ptr<rt::Bundle> bundle = load("waves");
    ASSERT_TRUE(bundle);
    std::unique_ptr<rt::Simulation> s = simulate(*bundle);
    ASSERT_TRUE(s);
    const rt::Water water = bundle->world().water.water();
    rt::LevelPolicy policy;
    policy.kind = rt::LevelPolicy::Kind::distance;
    policy.nearDistance = 50;
    policy.holdFrames = 0;
    std::string error;
    // 150 m away: 3 doublings beyond 50 m would be level -1, so the coarsest (0).
    policy.pointOfInterest = {150, 0, 0};
    ASSERT_TRUE(s->setLevelPolicy(policy, error)) << error;
    ASSERT_TRUE(s->advanceFrame(water, error)) << error;
    EXPECT_EQ(s->level(), 0u);
    // 80 m: within 100 m by more than the margin (15%): level 1; 112 m is beyond 100 m by less
    // than the margin: it stays.
    policy.pointOfInterest = {80, 0, 0};
    ASSERT_TRUE(s->setLevelPolicy(policy, error));
    ASSERT_TRUE(s->advanceFrame(water, error));
    EXPECT_EQ(s->level(), 1u);
    policy.pointOfInterest = {112, 0, 0};
    ASSERT_TRUE(s->setLevelPolicy(policy, error));
    ASSERT_TRUE(s->advanceFrame(water, error));
    EXPECT_EQ(s->level(), 1u);
    // Near: the finest; the snapshot is taken inside the switch's blend.
    policy.pointOfInterest = {10, 0, 0};
    ASSERT_TRUE(s->setLevelPolicy(policy, error));
    ASSERT_TRUE(s->advanceFrame(water, error));
    EXPECT_EQ(s->level(), 2u);
    const std::vector<std::uint8_t> snapshot = s->save();
    std::unique_ptr<rt::Simulation> copy = simulate(*bundle);
    ASSERT_TRUE(copy->restore(snapshot, error)) << error;
    ASSERT_TRUE(copy->setLevelPolicy(policy, error));
    EXPECT_EQ(copy->level(), 2u);
    for (int f = 0; f < 20; ++f) {
        ASSERT_TRUE(s->advanceFrame(water, error));
        ASSERT_TRUE(copy->advanceFrame(water, error));
        ASSERT_EQ(s->stateHash(), copy->stateHash()) << f;
    }
    // A snapshot without the level state (a bundle with one level's) does not fit.
    std::unique_ptr<rt::Bundle> older = load("older");
    std::unique_ptr<rt::Simulation> plain = simulate(*older);
    EXPECT_FALSE(copy->restore(plain->save(), error));
    // Policies out of range are refused.
    policy.nearDistance = 0;
    EXPECT_FALSE(s->setLevelPolicy(policy, error));
    EXPECT_NE(error.find("nearDistance"), std::string::npos);
}

TEST_F(RuntimeLevels, AtACoarserLevelTheSimulationStepsAsTheWorldWithFewerSteps) {
    // The box held at its coarsest level for 10 s on waves (importance 0 in the World, level 0
    // in the runtime), switched to it on the first frame: one step a frame where the finest
    // takes the project's four (the box's stable step needs one), in the World and the runtime
    // alike, which stay together (the blend of the switch included) as they do at the finest
    // level (test_runtime_trajectory.cpp's 1e-6 m). With fewerStepsWhenCoarser off both take
    // every sub-step; the longer step moves the box by less than the coarse level itself does
    // against the finest.
    std::unique_ptr<rt::Bundle> bundle = load("waves");
    ASSERT_TRUE(bundle);
    const rt::Water water = bundle->world().water.water();
    constexpr int kFrames = 600;
    struct Run {
        std::vector<Eigen::Vector3d> world, runtime;
        std::size_t evaluations = 0;
    };
    const auto run = [&](bool coarse, bool fewer) {
        Run r;
        std::unique_ptr<World> world = test::fastWorldOrFail(test::sceneOrFail(wavy(*project_)));
        std::unique_ptr<rt::Simulation> s = simulate(*bundle);
        if (!world || !s) return r;
        LevelPolicy policy;
        policy.kind = LevelPolicy::Kind::importance;
        policy.importance = {coarse ? 0.0 : 1.0};
        policy.fewerStepsWhenCoarser = fewer;
        EXPECT_TRUE(world->setLevelPolicy(policy).ok());
        rt::LevelPolicy fixed;
        fixed.kind = rt::LevelPolicy::Kind::fixed;
        fixed.level = coarse ? 0 : 2;
        fixed.fewerStepsWhenCoarser = fewer;
        std::string error;
        EXPECT_TRUE(s->setLevelPolicy(fixed, error)) << error;
        for (int f = 0; f < kFrames; ++f) {
            EXPECT_TRUE(world->advanceFrame().ok());
            EXPECT_TRUE(s->advanceFrame(water, error)) << error;
            r.world.push_back(world->bodies()[0].state.position);
            r.runtime.push_back(eigen(s->centerOfMass()));
        }
        EXPECT_EQ(world->bodies()[0].levelSize, coarse ? 16 : 64);
        EXPECT_EQ(s->level(), coarse ? 0u : 2u);
        r.evaluations = world->statistics().buoyancyEvaluations;
        return r;
    };
    const auto largestGap = [](const std::vector<Eigen::Vector3d>& a,
                               const std::vector<Eigen::Vector3d>& b) {
        double gap = 0;
        for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
            gap = std::max(gap, (a[i] - b[i]).norm());
        return gap;
    };
    const Run fewer = run(true, true), every = run(true, false), finest = run(false, true);
    ASSERT_EQ(fewer.world.size(), static_cast<std::size_t>(kFrames));
    ASSERT_EQ(every.world.size(), static_cast<std::size_t>(kFrames));
    ASSERT_EQ(finest.world.size(), static_cast<std::size_t>(kFrames));
    // The switch on the first frame evaluates both levels once.
    EXPECT_EQ(fewer.evaluations, static_cast<std::size_t>(kFrames + 2));
    EXPECT_EQ(every.evaluations, static_cast<std::size_t>(4 * kFrames + 2));
    EXPECT_EQ(finest.evaluations, static_cast<std::size_t>(4 * kFrames));
    const double worldRuntime = largestGap(fewer.world, fewer.runtime);
    const double steps = largestGap(fewer.world, every.world);
    const double level = largestGap(every.world, finest.world);
    std::printf(
        "  World and runtime at one step a frame %.2e m apart (%.2e at four); one step "
        "against four %.2e m, 16^2 against 64^2 %.2e m\n",
        worldRuntime, largestGap(every.world, every.runtime), steps, level);
    EXPECT_LE(worldRuntime, 1e-6);
    EXPECT_LE(largestGap(every.world, every.runtime), 1e-6);
    EXPECT_GT(steps, 1e-6);
    EXPECT_LT(steps, 0.5 * level);
}

TEST_F(RuntimeLevels, TheCApiReadsTheLevelsAndSetsThePolicy) {
    plimsoll_bundle* bundle = plimsoll_bundle_load((*root_ / "flat").string().c_str(), 1);
    ASSERT_TRUE(bundle) << plimsoll_runtime_last_error();
    ASSERT_EQ(plimsoll_bundle_level_count(bundle), 3u);
    plimsoll_level_info info{};
    info.struct_size = sizeof info;
    ASSERT_TRUE(plimsoll_bundle_level_query(bundle, 0, &info));
    EXPECT_EQ(info.size, 16);
    EXPECT_GT(info.force_error, 0.0);
    EXPECT_FALSE(plimsoll_bundle_level_query(bundle, 3, &info));
    plimsoll_simulation* simulation = plimsoll_simulation_create(bundle);
    ASSERT_TRUE(simulation) << plimsoll_runtime_last_error();
    EXPECT_EQ(plimsoll_simulation_level(simulation), 2u);
    plimsoll_level_policy policy = plimsoll_level_policy_default();
    EXPECT_EQ(policy.hold_frames, 30);
    policy.kind = PLIMSOLL_LEVEL_FIXED;
    policy.level = 1;
    policy.hold_frames = 0;
    ASSERT_TRUE(plimsoll_simulation_set_level_policy(simulation, &policy))
        << plimsoll_runtime_last_error();
    ASSERT_TRUE(plimsoll_simulation_advance_frame(simulation, nullptr))
        << plimsoll_runtime_last_error();
    EXPECT_EQ(plimsoll_simulation_level(simulation), 1u);
    policy.kind = 7;
    EXPECT_FALSE(plimsoll_simulation_set_level_policy(simulation, &policy));
    EXPECT_NE(std::string(plimsoll_runtime_last_error()).find("kind 7"), std::string::npos);
    plimsoll_simulation_destroy(simulation);
    // Fewer steps at coarser levels by default; a caller built before the field (its
    // struct_size ends before it) gets the default, and 0 takes every sub-step.
    EXPECT_EQ(plimsoll_level_policy_default().fewer_steps_when_coarser, 1);
    const auto hashAfter = [&](std::size_t structSize, int fewer) {
        plimsoll_simulation* s = plimsoll_simulation_create(bundle);
        plimsoll_level_policy p = plimsoll_level_policy_default();
        p.struct_size = structSize;
        p.kind = PLIMSOLL_LEVEL_FIXED;
        p.level = 0;
        p.hold_frames = 0;
        p.fewer_steps_when_coarser = fewer;
        EXPECT_TRUE(plimsoll_simulation_set_level_policy(s, &p)) << plimsoll_runtime_last_error();
        for (int f = 0; f < 60; ++f) EXPECT_TRUE(plimsoll_simulation_advance_frame(s, nullptr));
        const std::uint64_t hash = plimsoll_simulation_state_hash(s);
        plimsoll_simulation_destroy(s);
        return hash;
    };
    const std::uint64_t fewer = hashAfter(sizeof(plimsoll_level_policy), 1);
    const std::uint64_t older =
        hashAfter(offsetof(plimsoll_level_policy, fewer_steps_when_coarser), 0);
    const std::uint64_t every = hashAfter(sizeof(plimsoll_level_policy), 0);
    EXPECT_EQ(older, fewer);
    EXPECT_NE(every, fewer);
    plimsoll_bundle_destroy(bundle);
}

}  // namespace
}  // namespace test_runtime_levels
}  // namespace plimsoll
