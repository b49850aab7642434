// The Bullet adapter (engine/adapters/bullet): Plimsoll's water load applied to Bullet rigid
// bodies each substep, Bullet's collisions. Checked against the runtime's own integrator
// (plimsoll_instance_step), Archimedes' law for a crate on a deck, and a flooding boat that must
// end on the sea floor. The bundles are exported by `plimsoll export` from the sample projects.
#include "plimsoll_bullet.hpp"

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

/// A Bullet world with a few plain boxes (crates, the sea floor) beside the floating bodies.
struct Scene {
    btDefaultCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher{&configuration};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btDefaultMotionState>> motions;
    std::vector<std::unique_ptr<btRigidBody>> boxes;

    Scene() { world.setGravity(btVector3(0, -9.81f, 0)); }
    ~Scene() {
        for (auto& b : boxes) world.removeRigidBody(b.get());
    }
    btRigidBody* addBox(const btVector3& half, const btVector3& at, double mass) {
        shapes.push_back(std::make_unique<btBoxShape>(half));
        btVector3 inertia(0, 0, 0);
        if (mass > 0) shapes.back()->calculateLocalInertia(btScalar(mass), inertia);
        motions.push_back(
            std::make_unique<btDefaultMotionState>(btTransform(btQuaternion::getIdentity(), at)));
        boxes.push_back(std::make_unique<btRigidBody>(btScalar(mass), motions.back().get(),
                                                      shapes.back().get(), inertia));
        boxes.back()->setActivationState(DISABLE_DEACTIVATION);
        world.addRigidBody(boxes.back().get());
        return boxes.back().get();
    }
    void step(double dt) { world.stepSimulation(btScalar(dt), 1, btScalar(dt)); }
};

class BulletAdapter : public testing::Test {
protected:
    static void SetUpTestSuite() {
        root_ = new fs::path(fs::path(testing::TempDir()) /
                             ("bullet_adapter_" + std::to_string(::getpid())));
        fs::remove_all(*root_);
        fs::create_directories(*root_);
        const fs::path source = PLIMSOLL_SOURCE_DIR;
        fs::copy(source / "assets", *root_ / "assets", fs::copy_options::recursive);
        fs::copy(source / "projects", *root_ / "projects", fs::copy_options::recursive);
        for (const char* name : {"buoy", "box_half_draft", "damaged_boat"}) {
            // The adapter applies the water load only: no added mass or radiation memory
            // (docs/engine-integration.md), so the bodies it is compared with do not radiate.
            const fs::path project = *root_ / "projects" / (std::string(name) + ".plim.json");
            nlohmann::json doc = nlohmann::json::parse(std::ifstream(project));
            for (nlohmann::json& body : doc["bodies"]) body["radiation"] = false;
            std::ofstream(project) << doc.dump(2);
            const std::string command = std::string(PLIMSOLL_BINARY) + " export '" +
                                        project.string() + "' --out '" + (*root_ / "out").string() +
                                        "' > /dev/null 2>&1";
            ASSERT_EQ(std::system(command.c_str()), 0) << command;
        }
    }
    static void TearDownTestSuite() {
        fs::remove_all(*root_);
        delete root_;
    }
    /// The bundle of the first body of a sample project, destroyed when it goes out of scope
    /// (declared before the bodies made of it, it outlives them).
    using BundlePtr = std::unique_ptr<plimsoll_bundle, decltype(&plimsoll_bundle_destroy)>;
    static BundlePtr load(const std::string& project, const std::string& body) {
        BundlePtr b(plimsoll_bundle_load((*root_ / "out" / project / body).string().c_str(), 1),
                    &plimsoll_bundle_destroy);
        EXPECT_NE(b, nullptr) << plimsoll_runtime_last_error();
        return b;
    }
    static fs::path* root_;
};
fs::path* BulletAdapter::root_ = nullptr;

btVector3 centerOfMass(const plimsoll_bundle* b, const plimsoll_pose& pose) {
    const btTransform t(btQuaternion(btScalar(pose.orientation[1]), btScalar(pose.orientation[2]),
                                     btScalar(pose.orientation[3]), btScalar(pose.orientation[0])),
                        btVector3(btScalar(pose.position[0]), btScalar(pose.position[1]),
                                  btScalar(pose.position[2])));
    const plimsoll_mass m = plimsoll_bundle_mass(b);
    return t * btVector3(btScalar(m.center_of_mass[0]), btScalar(m.center_of_mass[1]),
                         btScalar(m.center_of_mass[2]));
}

/// Angle between two orientations (w, x, y, z), rad.
double angleBetween(const double a[4], const double b[4]) {
    const double d = std::abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
    return 2.0 * std::acos(std::min(1.0, d));
}

// A buoy let go 0.3 m high with a 12 degree heel and a spin, alone in the water: under the
// adapter Bullet integrates Plimsoll's load; the runtime's plimsoll_instance_step integrates the
// same load itself. Both are first-order (semi-implicit Euler; Bullet moves the orientation by
// the exponential map and adds the gyroscopic term implicitly, the runtime integrates angular
// momentum), in Bullet's float against double: over 3 s at 240 Hz, through the splash and the
// rolling, the centres of mass stay within 0.5 mm and the orientations within 0.2 degree (about
// 0.02 mm and 0.04 degree measured: the two differ at second order in dt per step).
TEST_F(BulletAdapter, AFreeBodyFollowsTheRuntimesOwnIntegrator) {
    // One bundle for both bodies: each is an instance of it.
    const BundlePtr buoy = load("buoy", "buoy");
    ASSERT_TRUE(buoy);
    const plimsoll_bundle* bullet = buoy.get();
    const plimsoll_bundle* alone = bullet;
    plimsoll_instance* aloneInstance = plimsoll_instance_create(alone);
    ASSERT_TRUE(aloneInstance) << plimsoll_runtime_last_error();
    const double heel = 12.0 * M_PI / 180.0;
    plimsoll_body_state state = {
        {{0.0, 0.3, 0.0}, {std::cos(heel / 2), 0.0, 0.0, std::sin(heel / 2)}},
        {{0.2, 0.0, -0.1}, {0.0, 0.8, 0.0}}};
    Scene scene;
    const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(bullet);
    plimsoll_bullet::Harbour harbour(&scene.world, water, fluid);
    const btTransform start(
        btQuaternion(btScalar(state.pose.orientation[1]), btScalar(state.pose.orientation[2]),
                     btScalar(state.pose.orientation[3]), btScalar(state.pose.orientation[0])),
        btVector3(0, 0.3f, 0));
    plimsoll_bullet::FloatingBody body(bullet, start);
    body.rigidBody()->setLinearVelocity(btVector3(0.2f, 0, -0.1f));
    body.rigidBody()->setAngularVelocity(btVector3(0, 0.8f, 0));
    harbour.add(&body);

    const double dt = 1.0 / 240.0;
    double worstPosition = 0, worstAngle = 0, lowest = 1e9;
    for (int step = 0; step < 720; ++step) {
        ASSERT_EQ(plimsoll_instance_step(aloneInstance, &state, &water, &fluid, step * dt, dt), 1)
            << plimsoll_runtime_last_error();
        scene.step(dt);
        ASSERT_EQ(harbour.error(), "");
        const plimsoll_pose p = body.pose();
        worstPosition =
            std::max(worstPosition,
                     double((centerOfMass(alone, state.pose) - centerOfMass(bullet, p)).length()));
        worstAngle = std::max(worstAngle, angleBetween(state.pose.orientation, p.orientation));
        lowest = std::min(lowest, double(centerOfMass(alone, state.pose).y()));
    }
    std::printf(
        "[ adapter  ] free buoy over 3 s: centres of mass at most %.2f mm apart, orientations %.3f "
        "deg\n",
        1e3 * worstPosition, worstAngle * 180.0 / M_PI);
    // The body did move through the water: it fell, splashed and came back up.
    EXPECT_LT(lowest, 0.1);
    EXPECT_LT(worstPosition, 5e-4);
    EXPECT_LT(worstAngle, 0.2 * M_PI / 180.0);
    plimsoll_instance_destroy(aloneInstance);
}

/// Mean height of the body's centre of mass over `seconds` after `settle` seconds.
double settledHeight(Scene& scene, plimsoll_bullet::FloatingBody& body, double settle,
                     double seconds) {
    const double dt = 1.0 / 240.0;
    for (int i = 0; i < int(settle / dt); ++i) scene.step(dt);
    double sum = 0;
    const int n = int(seconds / dt);
    for (int i = 0; i < n; ++i) {
        scene.step(dt);
        sum += body.rigidBody()->getCenterOfMassPosition().y();
    }
    return sum / n;
}

// The box of box_half_draft (1 x 0.5 x 0.25 m, 62.5 kg) floats flat; a 20 kg crate set on its
// deck must sink it by m / (rho A_waterplane) = 20 / (1000 x 0.5) = 40 mm (the box is
// wall-sided), within 2%. Bullet's velocity damping settles both; it moves no equilibrium.
TEST_F(BulletAdapter, ACrateOnTheDeckDeepensTheDraftByArchimedes) {
    const BundlePtr owned = load("box_half_draft", "box");
    const plimsoll_bundle* box = owned.get();
    ASSERT_TRUE(box);
    const plimsoll_mass m = plimsoll_bundle_mass(box);
    ASSERT_NEAR(m.mass, 62.5, 1e-6);
    Scene scene;
    const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
    plimsoll_bullet::Harbour harbour(&scene.world, water, plimsoll_bundle_default_fluid(box));
    // The 0.25 m edge (object z) vertical: 90 degrees about x.
    const btTransform flat(btQuaternion(btVector3(1, 0, 0), btScalar(M_PI / 2)),
                           btVector3(0, 0, 0));
    plimsoll_bullet::FloatingBody body(box, flat);
    body.rigidBody()->setDamping(0.9f, 0.9f);
    harbour.add(&body);
    const double before = settledHeight(scene, body, 2.0, 1.0);
    // Empty, the centre of mass floats at the water (half draft): a check of the load itself.
    // The load goes in as impulses, which Bullet's own velocity damping (0.9 here) then damps
    // in the same substep while it does not damp gravity's force: the equilibrium sits 1.2 mm
    // low (measured). The crate's Archimedes difference below is not affected.
    EXPECT_NEAR(before, 0.0, 2e-3);

    const double crateMass = 20.0;
    btRigidBody* crate = scene.addBox(btVector3(0.15f, 0.15f, 0.15f),
                                      btVector3(0, 0.125f + 0.15f + 0.002f, 0), crateMass);
    crate->setDamping(0.9f, 0.9f);
    const double after = settledHeight(scene, body, 4.0, 1.0);
    ASSERT_EQ(harbour.error(), "");
    const double expected = crateMass / (1000.0 * 1.0 * 0.5);
    std::printf("[ adapter  ] crate of %.0f kg: draft deeper by %.3f mm, Archimedes %.3f mm\n",
                crateMass, 1e3 * (before - after), 1e3 * expected);
    EXPECT_NEAR(before - after, expected, 0.02 * expected);
    // The crate rests on the deck (its bottom on the box's top face).
    EXPECT_NEAR(double(crate->getCenterOfMassPosition().y()), after + 0.125 + 0.15, 5e-3);
}

// The damaged boat floods through its stern; over a 3 m deep sea floor it must sink, land on
// the floor and rest there (Bullet's contact against the floor, Plimsoll's weight of the
// water inside against its buoyancy).
TEST_F(BulletAdapter, AFloodingBoatSinksOntoTheSeaFloorAndRests) {
    const BundlePtr owned = load("damaged_boat", "boat");
    const plimsoll_bundle* boat = owned.get();
    ASSERT_TRUE(boat);
    ASSERT_GT(plimsoll_graph_node_count(boat), 0u);
    double lo[3], hi[3];
    ASSERT_EQ(plimsoll_bundle_bounds(boat, lo, hi), 1);
    Scene scene;
    const double floor = -3.0;
    scene.addBox(btVector3(50, 0.5f, 50), btVector3(0, btScalar(floor - 0.5), 0), 0);
    const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
    plimsoll_bullet::Harbour harbour(&scene.world, water, plimsoll_bundle_default_fluid(boat));
    plimsoll_bullet::FloatingBody body(boat, btTransform::getIdentity());
    body.rigidBody()->setDamping(0.3f, 0.3f);
    harbour.add(&body);

    const double dt = 1.0 / 120.0;
    double restedFor = 0, bottom = 0;
    int step = 0;
    for (; step < int(300.0 / dt) && restedFor < 2.0; ++step) {
        scene.step(dt);
        ASSERT_EQ(harbour.error(), "");
        btVector3 aabbMin, aabbMax;
        body.rigidBody()->getAabb(aabbMin, aabbMax);
        bottom = aabbMin.y();
        const bool resting =
            bottom < floor + 0.05 && body.rigidBody()->getLinearVelocity().length() < 0.01f;
        restedFor = resting ? restedFor + dt : 0.0;
    }
    double inside = 0, capacity = 0;
    for (std::size_t n = 0; n < plimsoll_graph_node_count(boat); ++n) {
        double water = 0;
        ASSERT_EQ(plimsoll_instance_node_water(body.instance(), n, &water), 1)
            << plimsoll_runtime_last_error();
        inside += water;
        capacity += plimsoll_graph_node_capacity(boat, n);
    }
    std::printf(
        "[ adapter  ] flooding boat: on the floor after %.1f s, bottom %.3f m (floor %.1f), "
        "%.2f of %.2f m^3 of water inside\n",
        step * dt, bottom, floor, inside, capacity);
    EXPECT_GE(restedFor, 2.0) << "the boat did not come to rest on the floor; its bottom is at "
                              << bottom;
    EXPECT_NEAR(bottom, floor, 0.05);
    // It rests because the boat and its water outweigh the water the hull displaces.
    const plimsoll_load& load = body.lastLoad();
    EXPECT_GT(plimsoll_bundle_mass(boat).mass + load.water_mass,
              1000.0 * load.forces.submerged_volume);
}

/// A game's own pre-tick callback: counts its calls and checks the world's user info is still
/// the game's.
struct GameTicks {
    int calls = 0;
    int wrongUserInfo = 0;
};
void gamePreTick(btDynamicsWorld* world, btScalar) {
    auto* ticks = static_cast<GameTicks*>(world->getWorldUserInfo());
    if (!ticks) return;
    ++ticks->calls;
}

// The game keeps its own forces and callbacks: a 200 N thruster pushed with applyCentralForce
// before each stepSimulation accelerates the floating box by F / m in its first step (the
// load adds to it, it does not replace it), and the game's pre-tick callback, set before the
// Harbour, is still called every substep with the world's user info still the game's.
TEST_F(BulletAdapter, TheGamesForcesAndTickCallbackAreKept) {
    const BundlePtr owned = load("box_half_draft", "box");
    const plimsoll_bundle* box = owned.get();
    ASSERT_TRUE(box);
    const double mass = plimsoll_bundle_mass(box).mass;
    const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
    const btTransform flat(btQuaternion(btVector3(1, 0, 0), btScalar(M_PI / 2)),
                           btVector3(0, 0, 0));
    const double dt = 1.0 / 240.0, thrust = 200.0;
    // The same box without the thruster: what the water alone does in the first step.
    btVector3 waterOnly;
    {
        Scene scene;
        plimsoll_bullet::Harbour harbour(&scene.world, water, plimsoll_bundle_default_fluid(box));
        plimsoll_bullet::FloatingBody body(box, flat);
        harbour.add(&body);
        scene.step(dt);
        waterOnly = body.rigidBody()->getLinearVelocity();
    }
    Scene scene;
    GameTicks ticks;
    scene.world.setInternalTickCallback(&gamePreTick, &ticks, true);
    plimsoll_bullet::Harbour harbour(&scene.world, water, plimsoll_bundle_default_fluid(box));
    EXPECT_EQ(scene.world.getWorldUserInfo(), &ticks);
    plimsoll_bullet::FloatingBody body(box, flat);
    harbour.add(&body);
    const int steps = 480;
    for (int step = 0; step < steps; ++step) {
        body.rigidBody()->applyCentralForce(btVector3(btScalar(thrust), 0, 0));
        // Two substeps a call: the thruster's force holds for both.
        scene.world.stepSimulation(btScalar(2 * dt), 2, btScalar(dt));
        ASSERT_EQ(harbour.error(), "");
    }
    EXPECT_EQ(ticks.calls, 2 * steps);
    const double x = body.rigidBody()->getCenterOfMassPosition().x();
    std::printf(
        "[ adapter  ] 200 N thruster on the %.1f kg box: %.2f m in %.1f s; game's pre-tick "
        "callback "
        "called %d times\n",
        mass, x, 2 * steps * dt, ticks.calls);
    // Without drag the box would go F t^2 / 2m = 12.8 m in 4 s; the water's drag holds it back,
    // but far from the 0 m the thruster made when its force was cleared each substep.
    EXPECT_GT(x, 1.0);
    EXPECT_LT(x, 0.5 * thrust / mass * std::pow(2 * steps * dt, 2));

    // One step from rest, the thruster's F dt / m is on top of the water's own push, exactly.
    Scene once;
    GameTicks none;
    once.world.setInternalTickCallback(&gamePreTick, &none, true);
    plimsoll_bullet::Harbour again(&once.world, water, plimsoll_bundle_default_fluid(box));
    plimsoll_bullet::FloatingBody pushed(box, flat);
    again.add(&pushed);
    pushed.rigidBody()->applyCentralForce(btVector3(btScalar(thrust), 0, 0));
    once.step(dt);
    const btVector3 v = pushed.rigidBody()->getLinearVelocity();
    EXPECT_NEAR(v.x() - waterOnly.x(), thrust * dt / mass, 1e-5);
    EXPECT_NEAR(v.y(), waterOnly.y(), 1e-6);
    EXPECT_EQ(none.calls, 1);
}

/// A Gerstner-like swell: heights only (what the Harbour asks).
double swell(void*, double x, double, double t) { return 0.05 * std::sin(0.8 * x - 2.0 * t); }

// On calm water a floating box comes to rest and sleeps (it then costs no evaluation and its
// load is zero), and the game's push wakes it; on waves no body sleeps.
TEST_F(BulletAdapter, ABodyAtRestOnCalmWaterSleepsAndWavesKeepItAwake) {
    const BundlePtr owned = load("box_half_draft", "box");
    const plimsoll_bundle* box = owned.get();
    ASSERT_TRUE(box);
    const btTransform flat(btQuaternion(btVector3(1, 0, 0), btScalar(M_PI / 2)),
                           btVector3(0, 0.05f, 0));
    const double dt = 1.0 / 120.0;
    const plimsoll_water calm = {0.0, nullptr, nullptr, nullptr};
    Scene scene;
    plimsoll_bullet::Harbour harbour(&scene.world, calm, plimsoll_bundle_default_fluid(box));
    plimsoll_bullet::FloatingBody body(box, flat);
    // Bullet's velocity damping, as a game sets it, lets the bob die out within the run.
    body.rigidBody()->setDamping(0.5f, 0.5f);
    harbour.add(&body);
    double asleepAt = -1;
    for (int step = 0; step < int(60.0 / dt) && asleepAt < 0; ++step) {
        scene.step(dt);
        ASSERT_EQ(harbour.error(), "");
        if (!body.rigidBody()->isActive()) asleepAt = step * dt;
    }
    std::printf("[ adapter  ] box on calm water: asleep after %.1f s at height %.4f m\n", asleepAt,
                double(body.rigidBody()->getCenterOfMassPosition().y()));
    ASSERT_GT(asleepAt, 0.0) << "the box never slept on calm water";
    const btScalar restY = body.rigidBody()->getCenterOfMassPosition().y();
    for (int step = 0; step < 240; ++step) scene.step(dt);
    EXPECT_FALSE(body.rigidBody()->isActive());
    EXPECT_EQ(body.rigidBody()->getCenterOfMassPosition().y(), restY);  // asleep: not moved
    EXPECT_EQ(body.lastLoad().forces.submerged_volume, 0.0);            // and not evaluated
    // A push from the game wakes it, and the water carries it again.
    body.rigidBody()->activate();
    body.rigidBody()->applyCentralImpulse(btVector3(0, -20.0f, 0));
    scene.step(dt);
    EXPECT_TRUE(body.rigidBody()->isActive());
    EXPECT_GT(body.lastLoad().forces.submerged_volume, 0.0);

    // On waves the same box never sleeps.
    plimsoll_water waves = {0.0, swell, nullptr, nullptr};
    waves.has_bounds = 1;
    waves.min_height = -0.05;
    waves.max_height = 0.05;
    Scene wavy;
    plimsoll_bullet::Harbour sea(&wavy.world, waves, plimsoll_bundle_default_fluid(box));
    plimsoll_bullet::FloatingBody rocking(box, flat);
    rocking.rigidBody()->setDamping(0.5f, 0.5f);
    sea.add(&rocking);
    bool everAsleep = false;
    for (int step = 0; step < int(std::max(10.0, asleepAt + 5.0) / dt); ++step) {
        wavy.step(dt);
        ASSERT_EQ(sea.error(), "");
        everAsleep = everAsleep || !rocking.rigidBody()->isActive();
    }
    EXPECT_FALSE(everAsleep);
}

}  // namespace
