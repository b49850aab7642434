// World's external-force hook (World::setExternalForce) against the momentum it must add.
#include "plimsoll/scene/world.h"

#include "test_support.h"
#include "world_support.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace plimsoll {
namespace test_world_external_force {
namespace {

namespace fs = std::filesystem;

using test::ballProject;

TEST(WorldExternalForce, AddsItsImpulseToTheMomentaAndCanBeRemoved) {
    const Eigen::Vector3d g(0, -9.81, 0);
    Result<std::unique_ptr<World>> made =
        World::create(test::sceneOrFail(ballProject(-100.0, g)), createReferenceBackend());
    ASSERT_TRUE(made.ok()) << made.error().message;
    World& world = **made;
    const double m = world.bodies()[0].mass.mass;
    const double T = world.scene().simulation.timeStep;
    const Eigen::Vector3d force(3.0, 40.0, -7.0), torque(0.5, -0.25, 2.0);
    int calls = 0;
    ASSERT_TRUE(world
                    .setExternalForce(0,
                                      [&](const SimulatedBody&, const RigidBodyState&) {
                                          ++calls;
                                          return Wrench{force, torque};
                                      })
                    .ok());
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
    EXPECT_LT((world.bodies()[0].state.linearMomentum - again.linearMomentum - m * g * T).norm(),
              1e-9);
    EXPECT_FALSE(world.setExternalForce(5, {}).ok());
}

}  // namespace
}  // namespace test_world_external_force
}  // namespace plimsoll
