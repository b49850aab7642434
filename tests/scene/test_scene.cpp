// Scenes in memory: World takes bodies that hold their data (no file behind a generated mesh),
// and gravity is one vector that World follows in magnitude and refuses in a direction buoyancy
// does not model. Reading a project into a Scene is tests/project/test_scene_loader.cpp's.
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/scene.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/scene/world.h"

#include "test_support.h"
#include "world_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace plimsoll {
namespace test_scene {
namespace {

namespace fs = std::filesystem;

/// A 1 m cube of density 500 in still water, its centre `depth` below the surface.
Scene cubeScene(double depth, const Eigen::Vector3d& gravity) {
    BodyDesc desc;
    desc.name = "cube";
    desc.mesh = "cube (generated)";
    desc.textureSize = 32;
    desc.material.density = 500.0;
    desc.position = Eigen::Vector3d(0, -depth, 0);
    desc.dragCoefficient = 0;
    desc.linearDamping = desc.angularDamping = 0;
    Scene scene;
    scene.bodies.push_back(test::bodyOrFail(desc, makeBox(Eigen::Vector3d(1, 1, 1))));
    scene.water = WaterModel::flat(0.0);
    scene.simulation.gravity = gravity;
    return scene;
}

TEST(SceneGravity, BuoyancyAndWeightFollowItsMagnitude) {
    // Fully under water at rest: buoyancy rho |g| V up, weight m g down, whatever |g| is (a
    // Mars-like 3.71 m/s^2 against Earth's): the first step's velocity is (rho V - m) g dt / m.
    for (double g : {9.81, 3.71}) {
        SCOPED_TRACE(g);
        std::unique_ptr<World> world = test::worldOrFail(cubeScene(2.0, Eigen::Vector3d(0, -g, 0)));
        ASSERT_TRUE(world);
        ASSERT_TRUE(world->advanceFrame().ok());
        const SimulatedBody& cube = world->bodies()[0];
        EXPECT_NEAR(cube.buoyancy.submergedVolume, 1.0, 1e-9);
        EXPECT_NEAR(cube.buoyancy.force.y(), 1000.0 * g * 1.0, 1e-6 * 1000.0 * g);
        EXPECT_DOUBLE_EQ(cube.fluid.gravity, g);
        // Net upward force (1000 - 500) g: after the frame, v = 500 g T / 500 = g T.
        const double T = world->scene().simulation.timeStep;
        EXPECT_NEAR(linearVelocity(cube.state, cube.mass).y(), g * T, 1e-6 * g * T);
    }
}

TEST(SceneGravity, ZeroGravityIsAllowedAndLeavesABodyAtRest) {
    std::unique_ptr<World> world = test::worldOrFail(cubeScene(2.0, Eigen::Vector3d::Zero()));
    ASSERT_TRUE(world);
    const Eigen::Vector3d start = world->bodies()[0].state.position;
    for (int f = 0; f < 10; ++f) ASSERT_TRUE(world->advanceFrame().ok());
    EXPECT_NEAR(world->bodies()[0].buoyancy.submergedVolume, 1.0, 1e-9);
    EXPECT_EQ(world->bodies()[0].buoyancy.force.norm(), 0.0);
    EXPECT_EQ(world->bodies()[0].state.position, start);
}

TEST(SceneGravity, ATiltedOrUpwardGravityIsRefusedClearly) {
    for (const Eigen::Vector3d g :
         {Eigen::Vector3d(0.5, -9.8, 0), Eigen::Vector3d(0, -9.8, 1e-3),
          Eigen::Vector3d(0, 9.81, 0), Eigen::Vector3d(0, -std::nan(""), 0)}) {
        SCOPED_TRACE(g.transpose());
        Result<std::unique_ptr<World>> world =
            World::create(cubeScene(2.0, g), createReferenceBackend());
        ASSERT_FALSE(world.ok());
        EXPECT_EQ(world.error().kind, ErrorKind::unsupported);
        EXPECT_NE(world.error().message.find("does not point straight down (-y)"),
                  std::string::npos)
            << world.error().message;
    }
    // From a project, the adapter names the file and the JSON path.
    Project project;
    project.fileStem = "tilted";
    project.simulation.gravity = Eigen::Vector3d(1, -9.81, 0);
    Result<Scene> scene = loadScene(project);
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.error().kind, ErrorKind::unsupported);
    EXPECT_EQ(scene.error().message.rfind(
                  "tilted.plim.json: simulation.gravity: gravity (1, -9.81, 0)", 0),
              0u)
        << scene.error().message;
}

TEST(SceneGravity, WavesUnderAnotherGravityThanTheScenesAreRefused) {
    Project project;
    project.fileStem = "waves";
    project.water.kind = WaterModel::Kind::Gerstner;
    project.water.waves.push_back(GerstnerWave{});
    project.water.gravity = 9.5;
    Result<Scene> scene = loadScene(project);
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.error().kind, ErrorKind::schema);
    EXPECT_EQ(scene.error().message.rfind("waves.plim.json: water.gravity: 9.5 m/s^2", 0), 0u)
        << scene.error().message;
    // Agreeing, the scene loads (no bodies), and World gives the waves the scene's gravity.
    project.water.gravity = 9.81;
    EXPECT_TRUE(loadScene(project).ok());
    Scene moon = cubeScene(2.0, Eigen::Vector3d(0, -1.62, 0));
    moon.water = project.water;
    std::unique_ptr<World> world = test::worldOrFail(std::move(moon));
    ASSERT_TRUE(world);
    EXPECT_DOUBLE_EQ(world->scene().water.gravity, 1.62);
    WaterModel calm = WaterModel::flat(0.0);
    calm.gravity = 20.0;
    world->setWater(calm);
    EXPECT_DOUBLE_EQ(world->scene().water.gravity, 1.62);
}

TEST(SceneBodies, PartsThatDoNotFitTheDescriptionAreRefused) {
    BodyDesc desc;
    desc.name = "odd";
    desc.mesh = "odd.obj";
    desc.textureSize = 16;
    desc.material.density = 500.0;
    Result<SceneBody> noMesh = bakeSceneBody(desc, {});
    ASSERT_FALSE(noMesh.ok());
    EXPECT_EQ(noMesh.error().kind, ErrorKind::invalidArgument);
    EXPECT_EQ(noMesh.error().message, "body 'odd' (odd.obj): no mesh");

    const auto box = std::make_shared<const TriangleMesh>(makeBox(Eigen::Vector3d(1, 1, 1)));
    desc.waterGraph = WaterGraphDesc{};
    Result<SceneBody> noGraph = bakeSceneBody(desc, {.mesh = box});
    ASSERT_FALSE(noGraph.ok());
    EXPECT_EQ(noGraph.error().message, "body 'odd' (odd.obj): water graph named but none given");

    desc.waterGraph.reset();
    desc.meshFrames = {"odd_001.obj"};
    Result<SceneBody> noFrames = bakeSceneBody(desc, {.mesh = box});
    ASSERT_FALSE(noFrames.ok());
    EXPECT_EQ(noFrames.error().message,
              "body 'odd' (odd.obj): mesh_frames named but no frames given");
}

}  // namespace
}  // namespace test_scene
}  // namespace plimsoll
