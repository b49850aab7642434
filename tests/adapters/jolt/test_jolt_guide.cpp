// The Jolt guide's code (engine/runtime/examples/jolt/plimsoll_jolt.hpp, shown in
// docs/engine-integration.md) against a real Jolt: built only where JOLT_DIR names a JoltPhysics
// checkout (5.0 or later). Checked against the runtime's own integrator (plimsoll_instance_step),
// against itself with two collision steps per update (the load once per step, not summed), and
// with a force the game adds itself (kept, not erased). The bundles are exported by
// `plimsoll export` from the sample projects.
#include "plimsoll_jolt.hpp"

#include <Jolt/Core/Factory.h>
#include <Jolt/Core/JobSystemThreadPool.h>
#include <Jolt/Core/TempAllocator.h>
#include <Jolt/RegisterTypes.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

namespace Layers {
constexpr JPH::ObjectLayer kMoving = 0;
}  // namespace Layers

/// One object layer and one broad-phase layer: the floating bodies only.
class OneLayer final : public JPH::BroadPhaseLayerInterface {
public:
    JPH::uint GetNumBroadPhaseLayers() const override { return 1; }
    JPH::BroadPhaseLayer GetBroadPhaseLayer(JPH::ObjectLayer) const override {
        return JPH::BroadPhaseLayer(0);
    }
#if defined(JPH_EXTERNAL_PROFILE) || defined(JPH_PROFILE_ENABLED)
    const char* GetBroadPhaseLayerName(JPH::BroadPhaseLayer) const override { return "MOVING"; }
#endif
};
class AllCollideWithBroadPhase final : public JPH::ObjectVsBroadPhaseLayerFilter {
public:
    bool ShouldCollide(JPH::ObjectLayer, JPH::BroadPhaseLayer) const override { return true; }
};
class AllCollide final : public JPH::ObjectLayerPairFilter {
public:
    bool ShouldCollide(JPH::ObjectLayer, JPH::ObjectLayer) const override { return true; }
};

/// Jolt's process-wide set-up, once.
struct JoltRuntime {
    JoltRuntime() {
        JPH::RegisterDefaultAllocator();
        JPH::Factory::sInstance = new JPH::Factory();
        JPH::RegisterTypes();
    }
    ~JoltRuntime() {
        JPH::UnregisterTypes();
        delete JPH::Factory::sInstance;
        JPH::Factory::sInstance = nullptr;
    }
};

/// A Jolt world with gravity along -y, stepped on one worker thread.
struct Scene {
    OneLayer layers;
    AllCollideWithBroadPhase broadPhaseFilter;
    AllCollide pairFilter;
    JPH::TempAllocatorImpl temp{4 * 1024 * 1024};
    JPH::JobSystemThreadPool jobs{JPH::cMaxPhysicsJobs, JPH::cMaxPhysicsBarriers, 1};
    JPH::PhysicsSystem system;

    Scene() {
        system.Init(64, 0, 64, 64, layers, broadPhaseFilter, pairFilter);
        system.SetGravity(JPH::Vec3(0.0f, -9.81f, 0.0f));
    }
    void update(double dt, int collisionSteps) {
        system.Update(float(dt), collisionSteps, &temp, &jobs);
    }
};

/// The centre of mass of a pose of the bundle's object, world.
JPH::Vec3 centerOfMass(const plimsoll_bundle* b, const plimsoll_pose& pose) {
    const plimsoll_mass m = plimsoll_bundle_mass(b);
    const JPH::Quat q(float(pose.orientation[1]), float(pose.orientation[2]),
                      float(pose.orientation[3]), float(pose.orientation[0]));
    return JPH::Vec3(float(pose.position[0]), float(pose.position[1]), float(pose.position[2])) +
           q * JPH::Vec3(float(m.center_of_mass[0]), float(m.center_of_mass[1]),
                         float(m.center_of_mass[2]));
}

class JoltGuide : public testing::Test {
protected:
    static void SetUpTestSuite() {
        jolt_ = new JoltRuntime();
        root_ = new fs::path(fs::path(testing::TempDir()) /
                             ("jolt_guide_" + std::to_string(::getpid())));
        fs::remove_all(*root_);
        fs::create_directories(*root_);
        const fs::path source = PLIMSOLL_SOURCE_DIR;
        fs::copy(source / "assets", *root_ / "assets", fs::copy_options::recursive);
        fs::copy(source / "projects", *root_ / "projects", fs::copy_options::recursive);
        // The guide applies the water load only: no added mass or radiation memory, so the
        // buoy it is compared with does not radiate.
        const fs::path project = *root_ / "projects" / "buoy.plim.json";
        nlohmann::json doc = nlohmann::json::parse(std::ifstream(project));
        for (nlohmann::json& body : doc["bodies"]) body["radiation"] = false;
        std::ofstream(project) << doc.dump(2);
        const std::string command = std::string(PLIMSOLL_BINARY) + " export '" + project.string() +
                                    "' --out '" + (*root_ / "out").string() + "' > /dev/null 2>&1";
        ASSERT_EQ(std::system(command.c_str()), 0) << command;
    }
    static void TearDownTestSuite() {
        fs::remove_all(*root_);
        delete root_;
        delete jolt_;
    }
    using BundlePtr = std::unique_ptr<plimsoll_bundle, decltype(&plimsoll_bundle_destroy)>;
    using InstancePtr = std::unique_ptr<plimsoll_instance, decltype(&plimsoll_instance_destroy)>;
    static BundlePtr buoy() {
        BundlePtr b(plimsoll_bundle_load((*root_ / "out" / "buoy" / "buoy").string().c_str(), 1),
                    &plimsoll_bundle_destroy);
        EXPECT_NE(b, nullptr) << plimsoll_runtime_last_error();
        return b;
    }
    static InstancePtr instance(const plimsoll_bundle* b) {
        InstancePtr i(plimsoll_instance_create(b), &plimsoll_instance_destroy);
        EXPECT_NE(i, nullptr) << plimsoll_runtime_last_error();
        return i;
    }
    /// A buoy body in `scene`, let go at `state` (object origin, centre-of-mass velocities).
    static JPH::BodyID addBuoy(Scene& scene, const plimsoll_bundle* b,
                               const plimsoll_body_state& state) {
        const JPH::Quat q(float(state.pose.orientation[1]), float(state.pose.orientation[2]),
                          float(state.pose.orientation[3]), float(state.pose.orientation[0]));
        JPH::BodyCreationSettings settings = plimsoll_jolt::bodySettings(
            b, JPH::RVec3(state.pose.position[0], state.pose.position[1], state.pose.position[2]),
            q, Layers::kMoving);
        settings.mLinearVelocity =
            JPH::Vec3(float(state.velocity.linear[0]), float(state.velocity.linear[1]),
                      float(state.velocity.linear[2]));
        settings.mAngularVelocity =
            JPH::Vec3(float(state.velocity.angular[0]), float(state.velocity.angular[1]),
                      float(state.velocity.angular[2]));
        return scene.system.GetBodyInterface().CreateAndAddBody(settings,
                                                                JPH::EActivation::Activate);
    }
    static JoltRuntime* jolt_;
    static fs::path* root_;
};
JoltRuntime* JoltGuide::jolt_ = nullptr;
fs::path* JoltGuide::root_ = nullptr;

const plimsoll_water kFlat = {0.0, nullptr, nullptr, nullptr};

plimsoll_body_state heeledAndSpinning() {
    const double heel = 12.0 * M_PI / 180.0;
    return {{{0.0, 0.3, 0.0}, {std::cos(heel / 2), 0.0, 0.0, std::sin(heel / 2)}},
            {{0.2, 0.0, -0.1}, {0.0, 0.8, 0.0}}};
}

// A buoy let go 0.3 m high with a 12 degree heel and a spin: Jolt integrates the guide's
// impulses, plimsoll_instance_step integrates the same load itself. Both are semi-implicit
// Euler; Jolt in float, integrating the angular velocity (no gyroscopic term), the runtime in
// double, integrating angular momentum. Over 3 s at 240 Hz the centres of mass must stay within
// 2 mm and the orientations within 0.5 degree: bounds chosen from the Bullet adapter's
// measured 0.02 mm and 0.04 degree with room for Jolt's missing gyroscopic term.
TEST_F(JoltGuide, AFreeBuoyFollowsTheRuntimesOwnIntegrator) {
    const BundlePtr b = buoy();
    ASSERT_TRUE(b);
    const InstancePtr alone = instance(b.get()), floating = instance(b.get());
    plimsoll_body_state state = heeledAndSpinning();
    Scene scene;
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(b.get());
    plimsoll_jolt::WaterListener listener(kFlat, fluid);
    scene.system.AddStepListener(&listener);
    const JPH::BodyID body = addBuoy(scene, b.get(), state);
    listener.add(body, floating.get());

    const double dt = 1.0 / 240.0;
    double worstPosition = 0, worstAngle = 0, lowest = 1e9;
    for (int step = 0; step < 720; ++step) {
        ASSERT_EQ(plimsoll_instance_step(alone.get(), &state, &kFlat, &fluid, step * dt, dt), 1)
            << plimsoll_runtime_last_error();
        scene.update(dt, 1);
        ASSERT_EQ(listener.error(), "");
        const JPH::Vec3 jolt =
            JPH::Vec3(scene.system.GetBodyInterface().GetCenterOfMassPosition(body));
        const JPH::Vec3 runtime = centerOfMass(b.get(), state.pose);
        worstPosition = std::max(worstPosition, double((jolt - runtime).Length()));
        const JPH::Quat q = scene.system.GetBodyInterface().GetRotation(body);
        const double dot =
            std::abs(q.GetW() * state.pose.orientation[0] + q.GetX() * state.pose.orientation[1] +
                     q.GetY() * state.pose.orientation[2] + q.GetZ() * state.pose.orientation[3]);
        worstAngle = std::max(worstAngle, 2.0 * std::acos(std::min(1.0, dot)));
        lowest = std::min(lowest, double(runtime.GetY()));
    }
    std::printf(
        "[ jolt     ] free buoy over 3 s: centres of mass at most %.3f mm apart, orientations %.3f "
        "deg\n",
        1e3 * worstPosition, worstAngle * 180.0 / M_PI);
    EXPECT_LT(lowest, 0.1);  // it fell into the water and came back up
    EXPECT_LT(worstPosition, 2e-3);
    EXPECT_LT(worstAngle, 0.5 * M_PI / 180.0);
}

// Two collision steps per update call the listener twice with half the time each: the same
// motion as two updates of one step. A force added in every OnStep would add up over the
// collision steps (twice the buoyancy), which this tells apart by metres.
TEST_F(JoltGuide, TwoCollisionStepsAnUpdateGiveTheLoadOncePerStep) {
    const BundlePtr b = buoy();
    ASSERT_TRUE(b);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(b.get());
    const InstancePtr oneStep = instance(b.get()), twoSteps = instance(b.get());
    Scene a, c;
    plimsoll_jolt::WaterListener listenerA(kFlat, fluid), listenerC(kFlat, fluid);
    a.system.AddStepListener(&listenerA);
    c.system.AddStepListener(&listenerC);
    const JPH::BodyID bodyA = addBuoy(a, b.get(), heeledAndSpinning());
    const JPH::BodyID bodyC = addBuoy(c, b.get(), heeledAndSpinning());
    listenerA.add(bodyA, oneStep.get());
    listenerC.add(bodyC, twoSteps.get());
    const double frame = 1.0 / 60.0;
    double worst = 0;
    for (int i = 0; i < 180; ++i) {
        a.update(frame / 2, 1);
        a.update(frame / 2, 1);
        c.update(frame, 2);
        const JPH::RVec3 pa = a.system.GetBodyInterface().GetCenterOfMassPosition(bodyA);
        const JPH::RVec3 pc = c.system.GetBodyInterface().GetCenterOfMassPosition(bodyC);
        worst = std::max(worst, double(JPH::Vec3(pa - pc).Length()));
    }
    ASSERT_EQ(listenerA.error(), "");
    ASSERT_EQ(listenerC.error(), "");
    EXPECT_NEAR(listenerA.time(), listenerC.time(), 1e-9);
    std::printf("[ jolt     ] one against two collision steps over 3 s: %.4f mm apart\n",
                1e3 * worst);
    EXPECT_LT(worst, 1e-4);
}

// The game's own force (a 200 N thruster, added once per update through the body interface)
// stays: the guide never resets forces, so the thrusted buoy travels metres farther than its
// twin in the same 5 s.
TEST_F(JoltGuide, AForceTheGameAddsIsKept) {
    const BundlePtr b = buoy();
    ASSERT_TRUE(b);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(b.get());
    const InstancePtr thrusted = instance(b.get()), idle = instance(b.get());
    Scene scene;
    plimsoll_jolt::WaterListener listener(kFlat, fluid);
    scene.system.AddStepListener(&listener);
    plimsoll_body_state rest = {{{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0, 0.0}}, {{0, 0, 0}, {0, 0, 0}}};
    const JPH::BodyID withThruster = addBuoy(scene, b.get(), rest);
    rest.pose.position[2] = 20.0;
    const JPH::BodyID without = addBuoy(scene, b.get(), rest);
    listener.add(withThruster, thrusted.get());
    listener.add(without, idle.get());
    JPH::BodyInterface& bodies = scene.system.GetBodyInterface();
    for (int i = 0; i < 300; ++i) {
        bodies.AddForce(withThruster, JPH::Vec3(200.0f, 0.0f, 0.0f));
        scene.update(1.0 / 60.0, 1);
    }
    ASSERT_EQ(listener.error(), "");
    const double travelled = double(bodies.GetCenterOfMassPosition(withThruster).GetX());
    const double drifted = double(bodies.GetCenterOfMassPosition(without).GetX());
    std::printf("[ jolt     ] 200 N thruster over 5 s: %.2f m against %.2f m without\n", travelled,
                drifted);
    EXPECT_GT(travelled - drifted, 1.0);
    // Both still float: the water's load was applied to both all along.
    EXPECT_GT(double(bodies.GetCenterOfMassPosition(withThruster).GetY()), -1.0);
    EXPECT_GT(double(bodies.GetCenterOfMassPosition(without).GetY()), -1.0);
}

}  // namespace
