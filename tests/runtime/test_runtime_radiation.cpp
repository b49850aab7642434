// Wave radiation in the runtime (docs/bundle.md "Radiation"): the bundle carries the engine's
// Cummins model exactly; a radiating box released below rest decays, through the runtime's own
// step, with the period and logarithmic decrement that its fitted A and B predict, and its
// energy (the memory's included) falls at every turning point; the C API steps bit for bit as
// the C++ one and refuses what it must; a manifest whose memory could make energy is refused by
// its JSON path.
#include "decay_support.h"
#include "test_support.h"

#include "plimsoll/geometry/box.h"
#include "plimsoll/export/bundle.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/physics/cummins.h"
#include "plimsoll/project/project.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/scene/scene_radiation.h"

#include "plimsoll_runtime.h"
#include "plimsoll_runtime/runtime.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <numbers>
#include <vector>

namespace plimsoll {
namespace test_runtime_radiation {
namespace {

namespace fs = std::filesystem;
namespace rt = plimsoll_runtime;

constexpr double kWaterDensity = 1000, kGravity = 9.81;

/// A 2 m x 1 m x 2 m box of density 500 (half-immersed; wider than tall, so that it floats
/// upright: a cube at that density capsizes, and its roll would feed the memory) with radiation
/// on, no drag and no damping stand-in, exported once; and the same body without radiation.
class RuntimeRadiation : public testing::Test {
protected:
    static void SetUpTestSuite() {
        root_ = new fs::path(test::scratchFolder("runtime_radiation"));
        ASSERT_TRUE(writeObj(makeBox({2, 1, 2}), *root_ / "box.obj").ok());
        project_ = new Project();
        Project& p = *project_;
        p.name = "radiating_box";
        p.folder = *root_;
        p.medium.density = kWaterDensity;
        BodyDesc body;
        body.name = "box";
        body.mesh = "box.obj";
        body.textureSize = 128;
        body.material.density = 500;
        body.dragCoefficient = 0;
        body.linearDamping = body.angularDamping = 0;
        body.radiation = RadiationDesc{.panelEdge = 1.0, .frequencies = 8};
        p.bodies.push_back(body);
        Result<BundleReport> radiating = writeBodyBundle(p, 0, *root_ / "radiating");
        ASSERT_TRUE(radiating.ok()) << radiating.error().message;
        Project plain = p;
        plain.bodies[0].radiation->enabled = false;
        Result<BundleReport> without = writeBodyBundle(plain, 0, *root_ / "plain");
        ASSERT_TRUE(without.ok()) << without.error().message;
    }
    static void TearDownTestSuite() {
        fs::remove_all(*root_);
        delete root_;
        delete project_;
    }
    static std::unique_ptr<rt::Bundle> load(const std::string& name) {
        std::string error;
        std::unique_ptr<rt::Bundle> bundle = rt::loadBundle((*root_ / name).string(), error);
        EXPECT_TRUE(bundle) << error;
        return bundle;
    }
    static fs::path* root_;
    static Project* project_;
};
fs::path* RuntimeRadiation::root_ = nullptr;
Project* RuntimeRadiation::project_ = nullptr;

TEST_F(RuntimeRadiation, TheBundleCarriesTheEnginesCumminsModelExactly) {
    Result<SceneBody> body = loadSceneBody(*project_, 0, {});
    ASSERT_TRUE(body.ok()) << body.error().message;
    ASSERT_TRUE(body->radiation);
    const CumminsModel& model = body->radiation->model;
    std::unique_ptr<rt::Bundle> bundle = load("radiating");
    ASSERT_TRUE(bundle);
    EXPECT_EQ(bundle->schemaMinor(), plimsoll::kBundleSchemaMinor);
    const rt::Radiation* r = bundle->radiation();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->restVolume, body->radiation->restVolume);
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            EXPECT_EQ(r->addedMassInfinity[i][j], model.addedMassInfinity(i, j)) << i << j;
    EXPECT_FALSE(model.memory[kHeaveY].empty());
    for (int mode = 0; mode < 6; ++mode) {
        ASSERT_EQ(r->memory[mode].size(), model.memory[mode].size()) << "mode " << mode;
        for (std::size_t k = 0; k < model.memory[mode].size(); ++k) {
            EXPECT_EQ(r->memory[mode][k].gain, model.memory[mode][k].gain);
            EXPECT_EQ(r->memory[mode][k].frequency, model.memory[mode][k].frequency);
            EXPECT_EQ(r->memory[mode][k].dampingRatio, model.memory[mode][k].dampingRatio);
        }
    }
    std::unique_ptr<rt::Bundle> plain = load("plain");
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->radiation(), nullptr);
}

TEST_F(RuntimeRadiation, AReleasedBoxDecaysWithThePeriodAndDecrementOfItsAAndB) {
    std::unique_ptr<rt::Bundle> bundle = load("radiating");
    ASSERT_TRUE(bundle && bundle->radiation());
    const rt::Radiation& r = *bundle->radiation();
    const double mass = bundle->mass().mass;
    const double stiffness = kWaterDensity * kGravity * 4.0;  // the 4 m^2 waterplane
    rt::Water water;                                          // flat at 0
    rt::Fluid fluid;
    fluid.density = kWaterDensity;
    fluid.gravity = kGravity;
    fluid.dragCoefficient = 0;
    // The height at which the runtime's own buoyancy carries the weight (about 0.5 - m / 4 rho:
    // the sampled surface's volume is not the cube's to the last digit).
    double low = -0.4, high = 0.4;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (low + high);
        rt::Pose pose;
        pose.position = {0, mid, 0};
        const double lift =
            kWaterDensity * bundle->evaluate(pose, {}, water, fluid).submergedVolume;
        (lift > mass ? low : high) = mid;
    }
    const double restHeight = 0.5 * (low + high);
    EXPECT_NEAR(restHeight, 0.5 - mass / (4 * kWaterDensity), 1e-3);
    std::vector<MemoryTerm> heave;
    for (const rt::RadiationTerm& t : r.memory[kHeaveY])
        heave.push_back({t.gain, t.frequency, t.dampingRatio});
    const test::HeaveCoefficients fitted = [&](double omega) {
        return std::pair{r.addedMassInfinity[kHeaveY][kHeaveY] + fittedAddedMass(heave, omega),
                         fittedDamping(heave, omega)};
    };
    const test::DecayFigures predicted = test::predictedHeaveDecay(fitted, mass, stiffness);
    rt::BodyState state;
    state.pose.position = {0, restHeight - 0.02, 0};
    rt::Body body(*bundle);
    ASSERT_NE(body.radiation(), nullptr);
    const rt::RadiationMemory& memory = *body.radiation();
    const double dt = 1e-3;
    const int steps = static_cast<int>((test::kSanitizedBuild ? 3 : 6) * predicted.period / dt);
    std::vector<double> offset;
    double previousVelocity = 0, previousEnergy = HUGE_VAL, worstRise = -HUGE_VAL;
    const double scale = 0.5 * stiffness * 0.02 * 0.02;  // the energy the release puts in
    for (int n = 0; n < steps; ++n) {
        rt::stepBody(body, state, water, fluid, dt * n, dt);
        const double y = state.pose.position.y - restHeight, v = state.velocity.linear.y;
        offset.push_back(y);
        if (n > 0 && (v > 0) != (previousVelocity > 0)) {
            // At a turning point: the body's energy (its share of the added mass moves with
            // it) plus what the memory holds.
            const double energy =
                0.5 * (mass + memory.share() * r.addedMassInfinity[kHeaveY][kHeaveY]) * v * v +
                0.5 * stiffness * y * y + memory.energy();
            worstRise = std::max(worstRise, (energy - previousEnergy) / scale);

            previousEnergy = energy;
        }
        previousVelocity = v;
    }
    const test::DecayFigures measured = test::measuredDecay(offset, dt);
    std::printf(
        "  runtime box: period %.4f s (predicted %.4f, %+.2f%%), log decrement %.4f (predicted "
        "%.4f, "
        "%+.2f%%), worst energy rise %+.2e\n",
        measured.period, predicted.period, 100 * (measured.period / predicted.period - 1),
        measured.logDecrement, predicted.logDecrement,
        100 * (measured.logDecrement / predicted.logDecrement - 1), worstRise);
    EXPECT_NEAR(measured.period, predicted.period, 0.05 * predicted.period);
    EXPECT_NEAR(measured.logDecrement, predicted.logDecrement, 0.05 * predicted.logDecrement);
    EXPECT_LT(worstRise, 0.0);
    // The bare hydrostatic period 2 pi sqrt(m / C) is what a body without radiation has: the
    // added mass must have made this one longer by about sqrt((m + A) / m).
    const double bare = 2 * std::numbers::pi * std::sqrt(mass / stiffness);
    EXPECT_GT(measured.period, 1.1 * bare);
}

TEST_F(RuntimeRadiation, TheCApiStepsBitForBitAsTheCppOneAndRefusesWhatItMust) {
    const std::string folder = (*root_ / "radiating").string();
    plimsoll_bundle* bundle = plimsoll_bundle_load(folder.c_str(), 1);
    ASSERT_TRUE(bundle) << plimsoll_runtime_last_error();
    std::unique_ptr<rt::Bundle> reference = load("radiating");
    ASSERT_TRUE(reference);
    const rt::Radiation& r = *reference->radiation();

    plimsoll_radiation_info info{};
    ASSERT_EQ(plimsoll_bundle_radiation(bundle, &info), 1) << plimsoll_runtime_last_error();
    EXPECT_EQ(info.rest_volume, r.restVolume);
    EXPECT_EQ(info.added_mass_infinity[1][1], r.addedMassInfinity[1][1]);
    EXPECT_EQ(info.added_mass_infinity[3][5], r.addedMassInfinity[3][5]);
    for (int mode = 0; mode < 6; ++mode)
        EXPECT_EQ(info.memory_terms[mode], static_cast<int>(r.memory[mode].size()));

    plimsoll_radiation_memory* memory = plimsoll_radiation_memory_create(bundle);
    ASSERT_TRUE(memory) << plimsoll_runtime_last_error();
    rt::Body referenceBody(*reference);
    // Released tilted and moving, so that every mode and the share's changes are exercised.
    plimsoll_body_state state{};
    state.pose.position[1] = 0.3;
    const Eigen::Quaterniond tilt(Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 0, 0.5).normalized()));
    state.pose.orientation[0] = tilt.w();
    state.pose.orientation[1] = tilt.x();
    state.pose.orientation[2] = tilt.y();
    state.pose.orientation[3] = tilt.z();
    state.velocity.linear[0] = 0.4;
    state.velocity.angular[2] = 0.3;
    rt::BodyState s;
    s.pose.position = {0, 0.3, 0};
    s.pose.orientation = {tilt.w(), tilt.x(), tilt.y(), tilt.z()};
    s.velocity.linear = {0.4, 0, 0};
    s.velocity.angular = {0, 0, 0.3};
    plimsoll_water water{};
    const plimsoll_fluid fluid{kWaterDensity, kGravity, 0, 0};
    rt::Water cppWater;
    rt::Fluid cppFluid;
    cppFluid.density = kWaterDensity;
    cppFluid.gravity = kGravity;
    cppFluid.dragCoefficient = 0;
    const double dt = 1.0 / 240;
    double lowestShare = 1;
    for (int n = 0; n < 480; ++n) {
        ASSERT_EQ(plimsoll_body_step_radiating(bundle, &state, memory, &water, &fluid, n * dt, dt),
                  1)
            << plimsoll_runtime_last_error();
        rt::stepBody(referenceBody, s, cppWater, cppFluid, n * dt, dt);
        ASSERT_EQ(state.pose.position[0], s.pose.position.x) << "step " << n;
        ASSERT_EQ(state.pose.position[1], s.pose.position.y) << "step " << n;
        ASSERT_EQ(state.pose.orientation[1], s.pose.orientation.x) << "step " << n;
        ASSERT_EQ(state.velocity.angular[2], s.velocity.angular.z) << "step " << n;
        ASSERT_EQ(plimsoll_radiation_memory_energy(memory), referenceBody.radiation()->energy())
            << "step " << n;
        lowestShare = std::min(lowestShare, referenceBody.radiation()->share());
    }
    EXPECT_GT(referenceBody.radiation()->energy(), 0.0);
    EXPECT_LT(lowestShare, 1.0);  // released above its rest draft: the share grew as it fell in

    // The pieces an engine with its own integrator calls.
    plimsoll_radiation_load load{};
    ASSERT_EQ(plimsoll_radiation_memory_begin(memory, &state.pose, 0.5 * r.restVolume, &load), 1);
    EXPECT_EQ(load.share, 1.0);
    EXPECT_EQ(load.added_mass[1][1], r.addedMassInfinity[1][1]);
    EXPECT_EQ(load.added_inertia[0][0], r.addedMassInfinity[3][3]);
    ASSERT_EQ(plimsoll_radiation_memory_begin(memory, &state.pose, 0.1 * r.restVolume, &load), 1);
    EXPECT_DOUBLE_EQ(load.share, 0.2);
    EXPECT_EQ(load.previous_share, 1.0);
    EXPECT_DOUBLE_EQ(load.added_mass[1][1], 0.2 * r.addedMassInfinity[1][1]);
    EXPECT_EQ(plimsoll_radiation_memory_advance(memory, &state.pose, &state.velocity, dt), 1);

    // Refusals, each naming the call and the reason; the state is left as it was.
    const plimsoll_body_state before = state;
    EXPECT_EQ(plimsoll_body_step_radiating(bundle, &state, nullptr, &water, &fluid, 0, dt), 0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "plimsoll_body_step_radiating: memory is NULL");
    EXPECT_EQ(plimsoll_radiation_memory_begin(memory, &state.pose, std::nan(""), &load), 0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "submerged_volume must be finite");
    EXPECT_EQ(plimsoll_radiation_memory_advance(memory, &state.pose, &state.velocity, -1), 0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "dt must be finite and > 0");
    plimsoll_bundle* other = plimsoll_bundle_load(folder.c_str(), 1);
    ASSERT_TRUE(other);
    EXPECT_EQ(plimsoll_body_step_radiating(other, &state, memory, &water, &fluid, 0, dt), 0);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "made for another bundle");
    EXPECT_EQ(std::memcmp(&before, &state, sizeof state), 0);
    const std::string plainFolder = (*root_ / "plain").string();
    plimsoll_bundle* plain = plimsoll_bundle_load(plainFolder.c_str(), 1);
    ASSERT_TRUE(plain);
    EXPECT_EQ(plimsoll_radiation_memory_create(plain), nullptr);
    EXPECT_CONTAINS(plimsoll_runtime_last_error(), "exported without radiation");
    EXPECT_EQ(plimsoll_bundle_radiation(plain, &info), 0);
    plimsoll_radiation_memory_destroy(memory);
    plimsoll_bundle_free(plain);
    plimsoll_bundle_free(other);
    plimsoll_bundle_free(bundle);
}

TEST_F(RuntimeRadiation, AMemoryThatCouldMakeEnergyIsRefusedByItsPath) {
    const fs::path source = *root_ / "radiating";
    const std::string manifest = test::readFile(source / "manifest.json");
    const std::pair<std::function<void(nlohmann::json&)>, std::string> cases[] = {
        {[](nlohmann::json& m) { m["radiation"]["memory"][1][0]["gain"] = -1.0; },
         "$.radiation.memory[1][0].gain: must be finite and >= 0"},
        {[](nlohmann::json& m) { m["radiation"]["memory"][1][0]["damping_ratio"] = 0.0; },
         "$.radiation.memory[1][0].damping_ratio: must be finite and > 0"},
        {[](nlohmann::json& m) { m["radiation"]["added_mass_infinity"][1][1] = -500.0; },
         "$.radiation.added_mass_infinity[1][1]: must be >= 0"},
        {[](nlohmann::json& m) { m["radiation"]["added_mass_infinity"][0][1] = 7.0; },
         "$.radiation.added_mass_infinity: is not symmetric"},
        {[](nlohmann::json& m) { m["radiation"]["rest_volume"] = 0.0; },
         "$.radiation.rest_volume: must be finite and > 0"},
        {[](nlohmann::json& m) { m["radiation"]["memory"].erase(5); },
         "$.radiation.memory: expected 6 lists of filters"},
    };
    for (const auto& [edit, expected] : cases) {
        const fs::path folder = *root_ / "edited";
        fs::remove_all(folder);
        fs::copy(source, folder, fs::copy_options::recursive);
        nlohmann::json m = nlohmann::json::parse(manifest);
        ASSERT_TRUE(m["radiation"].is_object());
        edit(m);
        std::ofstream(folder / "manifest.json") << m.dump(2);
        std::string error;
        EXPECT_FALSE(rt::loadBundle(folder.string(), error, {.verifyChecksums = false}));
        EXPECT_CONTAINS(error, "manifest.json");
        EXPECT_CONTAINS(error, expected);
    }
}

// A radiating instance's snapshot holds its radiation memory: saved mid-decay, while the
// filters hold energy, and restored into an instance of the same bundle, the steps continue
// bit for bit; restored into an instance whose memory is at rest instead, they would not (the
// memory's force is part of every step), which the comparison with a fresh instance shows.
TEST_F(RuntimeRadiation, AnInstanceSnapshotCarriesItsRadiationMemory) {
    const std::string folder = (*root_ / "radiating").string();
    plimsoll_bundle* bundle = plimsoll_bundle_load(folder.c_str(), 1);
    ASSERT_TRUE(bundle) << plimsoll_runtime_last_error();
    plimsoll_instance* a = plimsoll_instance_create(bundle);
    plimsoll_instance* b = plimsoll_instance_create(bundle);
    plimsoll_instance* fresh = plimsoll_instance_create(bundle);
    ASSERT_TRUE(a && b && fresh);
    const plimsoll_water water{};
    const plimsoll_fluid fluid{kWaterDensity, kGravity, 0, 0};
    plimsoll_body_state state{};
    state.pose.position[1] = 0.25;
    state.pose.orientation[0] = 1;
    const double dt = 1.0 / 240;
    const int k = 157, steps = 400;
    plimsoll_body_state saved{};
    double energyAtK = 0;
    std::vector<unsigned char> snapshot;
    std::vector<plimsoll_body_state> states;
    for (int n = 0; n < steps; ++n) {
        if (n == k) {
            std::size_t size = 0;
            ASSERT_EQ(plimsoll_instance_save(a, nullptr, 0, &size), 1);
            snapshot.resize(size);
            ASSERT_EQ(plimsoll_instance_save(a, snapshot.data(), size, &size), 1);
            saved = state;
            energyAtK = plimsoll_instance_radiation_energy(a);
            EXPECT_GT(energyAtK, 0.0);
        }
        ASSERT_EQ(plimsoll_instance_step(a, &state, &water, &fluid, n * dt, dt), 1)
            << plimsoll_runtime_last_error();
        states.push_back(state);
    }
    ASSERT_EQ(plimsoll_instance_restore(b, snapshot.data(), snapshot.size()), 1)
        << plimsoll_runtime_last_error();
    EXPECT_EQ(plimsoll_instance_radiation_energy(b), energyAtK);
    EXPECT_EQ(plimsoll_instance_radiation_energy(fresh), 0.0);
    plimsoll_body_state restored = saved, atRest = saved;
    bool diverged = false;
    for (int n = k; n < steps; ++n) {
        ASSERT_EQ(plimsoll_instance_step(b, &restored, &water, &fluid, n * dt, dt), 1);
        ASSERT_EQ(plimsoll_instance_step(fresh, &atRest, &water, &fluid, n * dt, dt), 1);
        ASSERT_EQ(std::memcmp(&restored, &states[n], sizeof restored), 0) << "step " << n;
        diverged = diverged || std::memcmp(&atRest, &states[n], sizeof atRest) != 0;
    }
    EXPECT_TRUE(diverged)
        << "a memory at rest gave the same steps: the snapshot test would be vacuous";
    EXPECT_EQ(plimsoll_instance_state_hash(b), plimsoll_instance_state_hash(a));
    plimsoll_instance_destroy(a);
    plimsoll_instance_destroy(b);
    plimsoll_instance_destroy(fresh);
    plimsoll_bundle_destroy(bundle);
}

}  // namespace
}  // namespace test_runtime_radiation
}  // namespace plimsoll
