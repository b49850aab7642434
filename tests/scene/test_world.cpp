// The world stepped through time: equilibrium drafts against analytic answers, stability at
// the extremes, what is skipped, deforming bodies.
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/world.h"

#include "test_support.h"
#include "world_support.h"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace plimsoll {
namespace test_world {
namespace {

namespace fs = std::filesystem;

/// One body of `mesh` (generated, in memory) with `density` in a fluid of `fluidDensity`.
Scene oneBody(const TriangleMesh& mesh, double density, double fluidDensity,
              const Eigen::Vector3d& rotationDeg = Eigen::Vector3d::Zero()) {
    BodyDesc body;
    body.name = "body";
    body.mesh = "generated";
    body.textureSize = 96;
    body.material.density = density;
    body.rotationDegrees = rotationDeg;
    // Strong damping so that 20 s settle to 1e-4 m/s from a start at the waterline.
    body.linearDamping = 4.0;
    body.angularDamping = 4.0;
    Scene scene;
    scene.bodies.push_back(test::bodyOrFail(body, mesh));
    scene.medium.density = fluidDensity;
    scene.water = WaterModel::flat(0.0);
    return scene;
}

void run(World& world, double seconds) {
    const int frames = static_cast<int>(std::round(seconds / world.scene().simulation.timeStep));
    for (int i = 0; i < frames; ++i) ASSERT_TRUE(world.advanceFrame().ok());
}

/// Depth of the lowest point of the body's mesh below the water after settling.
double settledDraft(const TriangleMesh& mesh, double density, const Eigen::Vector3d& rotationDeg,
                    double seconds, double* speed) {
    std::unique_ptr<World> world =
        test::fastWorldOrFail(oneBody(mesh, density, 1000.0, rotationDeg));
    run(*world, seconds);
    const SimulatedBody& body = world->bodies().front();
    *speed = linearVelocity(body.state, body.mass).norm();
    double lowest = 1e300;
    for (const auto& p : mesh.positions) lowest = std::min(lowest, body.pose().apply(p).y());
    return -lowest;
}

TEST(WorldEquilibrium, FlatBoxOfHalfDensityFloatsAtHalfItsHeight) {
    const TriangleMesh box = makeBox(Eigen::Vector3d(1.0, 0.25, 0.8));
    double speed = 0;
    const double draft = settledDraft(box, 500.0, Eigen::Vector3d::Zero(), 20.0, &speed);
    EXPECT_NEAR(draft, 0.125, 0.005 * 0.125);
    EXPECT_LT(speed, 1e-4);
    std::printf("  flat box: draft %.6f m, analytic 0.125 m (%.2e), speed %.1e m/s\n", draft,
                draft / 0.125 - 1, speed);
}

TEST(WorldEquilibrium, SphereAtQuarterAndThreeQuarterDensity) {
    const TriangleMesh sphere = makeUvSphere(0.5, 48, 24);
    const double volume = exactSolidMassProperties(sphere, 1.0).volume;
    for (double ratio : {0.25, 0.75}) {
        // The draft at which the exact clip of this very mesh displaces ratio x volume.
        double lo = 0.0, hi = 1.0;
        for (int i = 0; i < 60; ++i) {
            const double mid = 0.5 * (lo + hi);
            BodyFrame frame;
            frame.pose.translation = Eigen::Vector3d(0, 0.5 - mid, 0);
            const double v = evaluateBuoyancyExact(sphere, frame, 0.0, {}).submergedVolume;
            (v < ratio * volume ? lo : hi) = mid;
        }
        double speed = 0;
        const double draft =
            settledDraft(sphere, 1000.0 * ratio, Eigen::Vector3d::Zero(), 20.0, &speed);
        EXPECT_NEAR(draft, lo, 0.005 * lo) << ratio;
        EXPECT_LT(speed, 1e-4) << ratio;
        std::printf("  sphere at %.2f: draft %.6f m, exact clip %.6f m (%.2e), speed %.1e m/s\n",
                    ratio, draft, lo, draft / lo - 1, speed);
    }
}

TEST(WorldEquilibrium, LyingCylinderAtItsSegmentDraft) {
    // A horizontal cylinder: the submerged cross-section is a circular segment, area
    // r^2 (theta - sin theta) / 2 with draft r (1 - cos(theta / 2)).
    const double r = 0.3;
    const TriangleMesh cylinder = makeCylinder(r, 1.0, 64);
    const double n = 64;
    const double section = 0.5 * n * r * r * std::sin(2 * std::numbers::pi / n);  // prism
    for (double ratio : {0.25, 0.75}) {
        double lo = 0, hi = 2 * std::numbers::pi;
        for (int i = 0; i < 80; ++i) {
            const double mid = 0.5 * (lo + hi);
            (0.5 * r * r * (mid - std::sin(mid)) < ratio * section ? lo : hi) = mid;
        }
        const double expected = r * (1 - std::cos(lo / 2));
        double speed = 0;
        const double draft =
            settledDraft(cylinder, 1000.0 * ratio, Eigen::Vector3d(90, 0, 0), 20.0, &speed);
        EXPECT_NEAR(draft, expected, 0.005 * expected) << ratio;
        std::printf("  lying cylinder at %.2f: draft %.6f m, analytic %.6f m (%.2e)\n", ratio,
                    draft, expected, draft / expected - 1);
        EXPECT_LT(speed, 1e-4) << ratio;
    }
}

TEST(WorldSkips, BodiesOutOfTheWaterSkipTheKernels) {
    Scene scene = oneBody(makeUvSphere(0.5, 24, 12), 500.0, 1000.0);
    scene.bodies[0].desc.position = Eigen::Vector3d(0, 50, 0);
    std::vector<std::string> log;
    Result<std::unique_ptr<World>> world = World::create(
        scene, createReferenceBackend(), [&](const std::string& line) { log.push_back(line); });
    ASSERT_TRUE(world.ok());
    run(**world, 0.5);
    EXPECT_EQ((*world)->statistics().buoyancyEvaluations, 0u);
    EXPECT_EQ((*world)->statistics().skippedOutOfWater, (*world)->statistics().steps);
    EXPECT_EQ((*world)->statistics().massRecomputations, 0u);  // rigid: computed once
    bool said = false;
    for (const auto& line : log)
        said = said || line.find("skips the buoyancy kernels") != std::string::npos;
    EXPECT_TRUE(said);
    // Free fall meanwhile: v = g t.
    const SimulatedBody& body = (*world)->bodies().front();
    EXPECT_NEAR(linearVelocity(body.state, body.mass).y(), -9.81 * (*world)->time(), 1e-9);
}

TEST(WorldMaterials, RepaintingRecomputesTheMassOnceAndTheBodyStaysPut) {
    std::unique_ptr<World> world =
        test::worldOrFail(oneBody(makeUvSphere(0.5, 24, 12), 500.0, 1000.0));
    run(*world, 0.2);
    EXPECT_EQ(world->statistics().massRecomputations, 0u);
    const Eigen::Vector3d before = world->bodies()[0].state.position;
    MaterialDesc heavier;
    heavier.density = 800.0;
    heavier.shellSurfaceDensity = 5.0;
    ASSERT_TRUE(world->setMaterial(0, heavier).ok());
    const SimulatedBody& body = world->bodies()[0];
    EXPECT_EQ(world->statistics().massRecomputations, 1u);
    const double expected = 800.0 * body.volume + 5.0 * body.textures.surfaceArea();
    EXPECT_NEAR(body.mass.mass, expected, 1e-9 * expected);
    EXPECT_LT((body.state.position - before).norm(), 1e-9);  // a uniform ball: same centre
    run(*world, 0.2);
    EXPECT_EQ(world->statistics().massRecomputations, 1u);  // not again while unchanged
}

TEST(WorldDeforming, TheBalloonRecomputesOnlyWhenItsFrameChanges) {
    Project project;
    project.folder = PLIMSOLL_ASSETS_DIR;
    BodyDesc balloon;
    balloon.name = "balloon";
    balloon.mesh = "balloon/frame_000.obj";
    for (int k = 1; k < 24; ++k) {
        char name[64];
        std::snprintf(name, sizeof name, "balloon/frame_%03d.obj", k);
        balloon.meshFrames.push_back(name);
    }
    balloon.framesPerSecond = 12.0;
    balloon.textureSize = 48;
    balloon.material.shellSurfaceDensity = 0.05;
    project.bodies.push_back(balloon);
    project.medium.density = 1.225;
    project.water = WaterModel::flat(100.0);
    std::unique_ptr<World> world = test::worldOrFail(test::sceneOrFail(project));
    const double firstVolume = world->bodies()[0].volume;
    run(*world, 1.0);  // steps start at t < 1 s: mesh frames 1 .. 11 were shown
    EXPECT_EQ(world->statistics().massRecomputations, 11u);
    // Frame 11 of 24: r = 0.3 * 2^(11/23); the texture volume follows the mesh's.
    const double growth = std::pow(2.0, 3.0 * 11.0 / 23.0);
    EXPECT_NEAR(world->bodies()[0].volume / firstVolume, growth, 1e-3 * growth);
}

}  // namespace
}  // namespace test_world
}  // namespace plimsoll
