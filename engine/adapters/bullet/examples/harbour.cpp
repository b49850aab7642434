// A boat from a bundle floating beside a dock with crates: Plimsoll supplies buoyancy, drag
// and flooding (plimsoll_bullet::Harbour), Bullet the collisions of the hull, the dock, the
// crates and the sea floor. Prints the boat's height, heel and water inside once a second.
//   plimsoll_harbour BUNDLE_FOLDER [SECONDS]
#include "plimsoll_bullet.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: plimsoll_harbour BUNDLE_FOLDER [SECONDS]\n");
        return 2;
    }
    const double seconds = argc > 2 ? std::atof(argv[2]) : 20.0;
    plimsoll_bundle* bundle = plimsoll_bundle_load(argv[1], 1);
    if (!bundle) {
        std::fprintf(stderr, "plimsoll_harbour: %s\n", plimsoll_runtime_last_error());
        return 1;
    }
    btDefaultCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher(&configuration);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
    world.setGravity(btVector3(0, -9.81f, 0));

    const plimsoll_water water = {0.0, nullptr, nullptr, nullptr};
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(bundle);
    plimsoll_bullet::Harbour harbour(&world, water, fluid);

    double lo[3], hi[3];
    plimsoll_bundle_bounds(bundle, lo, hi);
    // The boat starts level with its origin on the water.
    plimsoll_bullet::FloatingBody boat(bundle, btTransform::getIdentity());
    harbour.add(&boat);

    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btDefaultMotionState>> motions;
    std::vector<std::unique_ptr<btRigidBody>> bodies;
    auto addBox = [&](const btVector3& half, const btVector3& at, double mass) {
        shapes.push_back(std::make_unique<btBoxShape>(half));
        btVector3 inertia(0, 0, 0);
        if (mass > 0) shapes.back()->calculateLocalInertia(btScalar(mass), inertia);
        motions.push_back(
            std::make_unique<btDefaultMotionState>(btTransform(btQuaternion::getIdentity(), at)));
        bodies.push_back(std::make_unique<btRigidBody>(btScalar(mass), motions.back().get(),
                                                       shapes.back().get(), inertia));
        bodies.back()->setActivationState(DISABLE_DEACTIVATION);
        world.addRigidBody(bodies.back().get());
        return bodies.back().get();
    };
    // Sea floor 4 m down; a dock 1 m beside the hull, its top 0.6 m above the water.
    addBox(btVector3(50, 0.5f, 50), btVector3(0, -4.5f, 0), 0);
    const float dockX = float(hi[0]) + 1.0f + 2.0f;
    addBox(btVector3(2.0f, 2.3f, 8.0f), btVector3(dockX, -1.7f, 0), 0);
    // Three crates on the dock, two on the deck.
    const float crate = 0.25f;
    std::vector<btRigidBody*> crates;
    for (int i = 0; i < 3; ++i)
        crates.push_back(addBox(btVector3(crate, crate, crate),
                                btVector3(dockX, 0.6f + crate + 0.01f, -2.0f + 2.0f * i), 40));
    for (int i = 0; i < 2; ++i)
        crates.push_back(addBox(btVector3(crate, crate, crate),
                                btVector3(0, float(hi[1]) + crate + 0.05f, -1.0f + 2.0f * i), 40));

    const double dt = 1.0 / 240.0;
    const int steps = static_cast<int>(seconds / dt + 0.5);
    for (int step = 0; step <= steps; ++step) {
        if (step % 240 == 0) {
            const btTransform& t = boat.rigidBody()->getCenterOfMassTransform();
            const double heel =
                std::acos(std::fmin(1.0, std::fabs(double(t.getBasis()[1][1])))) * 180.0 / M_PI;
            std::printf(
                "t %5.1f s  boat height %+.3f m  heel %5.2f deg  water inside %7.1f kg  crates y:",
                harbour.time(), double(t.getOrigin().y()), heel, boat.lastLoad().water_mass);
            for (btRigidBody* c : crates)
                std::printf(" %+.2f", double(c->getCenterOfMassPosition().y()));
            std::printf("\n");
        }
        if (!harbour.error().empty()) {
            std::fprintf(stderr, "plimsoll_harbour: %s\n", harbour.error().c_str());
            return 1;
        }
        if (step < steps) world.stepSimulation(btScalar(dt), 1, btScalar(dt));
    }
    for (auto& b : bodies) world.removeRigidBody(b.get());
    return 0;
}
