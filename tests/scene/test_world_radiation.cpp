// Radiation through the World (Cummins' equation with the rigid body, world.h): free heave
// decays of a hemisphere and a box whose damped period and logarithmic decrement must follow
// from the panel method's A and B at the natural frequency, energy (the memory's included)
// that never grows, a dropped light box that settles, and a body without radiation untouched.
#include "plimsoll/geometry/box.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/radiation_decay.h"
#include "plimsoll/scene/scene_radiation.h"
#include "plimsoll/scene/world.h"

#include "decay_support.h"
#include "test_support.h"
#include "world_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace plimsoll {
namespace test_world_radiation {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kGravity = 9.81, kDensity = 1025;

/// A 1 m cube's faces split to 16 panels each (the default panel edge, cbrt(V) / 2, makes a
/// few hundred with the lid: a bake several times longer).
const RadiationDesc kCoarseBox{.panelEdge = 0.5, .frequencies = 12};

/// One body of `mesh` and `density` in still water, with radiation `radiation` (null: none),
/// its object origin released at `height` above the surface, at rest.
struct Floating {
    Scene scene;
    std::shared_ptr<const BodyRadiation> radiation;  ///< computed even when the body runs without
};

Floating floating(const TriangleMesh& mesh, double density, bool withRadiation,
                  const RadiationDesc& desc = {}) {
    BodyDesc body;
    body.name = "body";
    body.mesh = "generated";
    body.textureSize = 128;
    body.material.density = density;
    body.dragCoefficient = 0;
    body.linearDamping = body.angularDamping = 0;
    if (withRadiation) body.radiation = desc;
    Floating out;
    out.scene.medium.density = kDensity;
    out.scene.water = WaterModel::flat(0.0);
    out.scene.simulation.gravity = {0, -kGravity, 0};
    out.scene.bodies.push_back(test::bodyOrFail(body, mesh));
    Result<BodyRadiation> radiation = computeBodyRadiation(
        out.scene.bodies[0], desc, out.scene.medium, out.scene.simulation.gravity);
    EXPECT_TRUE(radiation.ok()) << (radiation.ok() ? "" : radiation.error().message);
    if (radiation) out.radiation = std::make_shared<const BodyRadiation>(std::move(*radiation));
    if (withRadiation) out.scene.bodies[0].radiation = out.radiation;
    return out;
}

/// The heave record of a world run: centre-of-mass offsets from `rest` every frame, the energy
/// at the turning points, and when the body last moved at 1 mm/s or more.
struct Record {
    std::vector<double> offset;
    double worstEnergyRise = -1e300;  ///< over `scale`, from one turning point to the next
    double settleTime = -1;           ///< s; -1: never moved that fast
    double finalSpeed = 0;
};

/// `scale` (J): the energy the release puts in, which the rises are measured against.
Record run(World& world, double rest, double seconds, double scale) {
    Record r;
    double previousEnergy = world.mechanicalEnergy(0), previousVelocity = 0;
    const int frames = static_cast<int>(std::round(seconds / world.scene().simulation.timeStep));
    for (int f = 0; f < frames; ++f) {
        EXPECT_TRUE(world.advanceFrame().ok());
        const SimulatedBody& b = world.bodies()[0];
        r.offset.push_back(b.state.position.y() - rest);
        const Eigen::Vector3d v = linearVelocity(b.state, b.mass);
        if (f > 0 && (v.y() > 0) != (previousVelocity > 0)) {
            const double e = world.mechanicalEnergy(0);
            r.worstEnergyRise = std::max(r.worstEnergyRise, (e - previousEnergy) / scale);
            previousEnergy = e;
        }
        previousVelocity = v.y();
        if (v.norm() >= 1e-3) r.settleTime = world.time();
        r.finalSpeed = v.norm();
    }
    return r;
}

/// Released 2 cm below rest, the World's decay against A and B at the natural frequency.
void expectWorldDecayFollowsCoefficients(const char* name, const TriangleMesh& mesh, double density,
                                         double waterplaneArea, const RadiationDesc& desc) {
    Floating f = floating(mesh, density, true, desc);
    ASSERT_TRUE(f.radiation);
    const BodyRadiation& radiation = *f.radiation;
    const double mass = f.scene.bodies[0].mass->mass;
    const double restCentre = radiation.restHeight + f.scene.bodies[0].mass->centerOfMass.y();
    f.scene.bodies[0].desc.position = {0, radiation.restHeight - 0.02, 0};
    f.scene.simulation.timeStep = 1.0 / 240;
    f.scene.simulation.subSteps = 4;  // 1 ms steps
    // The panel solution itself at the natural frequency gives the prediction.
    Result<RestRadiationSurface> surface =
        restRadiationSurface(f.scene.bodies[0], desc, f.scene.medium, f.scene.simulation.gravity);
    ASSERT_TRUE(surface.ok());
    const RadiationSolver& solver = *surface->solver;
    // The mesh's own waterplane (a polygon, not the circle): rho g dV/dh at rest.
    auto displaced = [&](double h) {
        return wettedVolume(wettedPanels(
            mesh, Eigen::Affine3d(Eigen::Translation3d(0, radiation.restHeight + h, 0))));
    };
    const double stiffness = kDensity * kGravity * (displaced(-1e-4) - displaced(1e-4)) / 2e-4;
    EXPECT_NEAR(stiffness, kDensity * kGravity * waterplaneArea,
                0.03 * kDensity * kGravity * waterplaneArea);
    double omega = 0;
    const test::DecayFigures predicted = test::predictedHeaveDecay(solver, mass, stiffness, &omega);
    std::unique_ptr<World> world = test::fastWorldOrFail(f.scene);
    ASSERT_TRUE(world);
    // Three periods in the sanitized build (about twenty times slower): still the two periods the
    // measured period and decrement need.
    const Record r = run(*world, restCentre, (test::kSanitizedBuild ? 3 : 6) * predicted.period,
                         0.5 * stiffness * 0.02 * 0.02);
    const test::DecayFigures measured =
        test::measuredDecay(r.offset, world->scene().simulation.timeStep);
    std::printf(
        "  %s through the World: %zu panels, period %.4f s (predicted %.4f, %+.2f%%), log "
        "decrement %.4f "
        "(predicted %.4f, %+.2f%%), worst energy rise %+.2e\n",
        name, radiation.panelCount, measured.period, predicted.period,
        100 * (measured.period / predicted.period - 1), measured.logDecrement,
        predicted.logDecrement, 100 * (measured.logDecrement / predicted.logDecrement - 1),
        r.worstEnergyRise);
    EXPECT_NEAR(measured.period, predicted.period, 0.05 * predicted.period);
    EXPECT_NEAR(measured.logDecrement, predicted.logDecrement, 0.05 * predicted.logDecrement);
    EXPECT_LT(r.worstEnergyRise, 0.0);
}

TEST(WorldRadiation, HemisphereHeaveDecayFollowsAAndB) {
    // A sphere of radius 1 at half the water's density floats with its centre on the surface.
    // The default panel edge keeps the sphere's own 176 panels.
    expectWorldDecayFollowsCoefficients("hemisphere", makeUvSphere(1.0, 16, 12), kDensity / 2, kPi,
                                        {});
}

TEST(WorldRadiation, BoxHeaveDecayFollowsAAndB) {
    expectWorldDecayFollowsCoefficients("box", makeBox({1, 1, 1}), kDensity / 2, 1.0, kCoarseBox);
}

TEST(WorldRadiation, TheDecayTestButtonsRunMeasuresWhatAAndBPredict) {
    // runHeaveDecayTest (the editor's "Decay test"): the box above, from the scene as loaded
    // (released from wherever the project puts it), predicted from its stored coefficients.
    Floating f = floating(makeBox({1, 1, 1}), kDensity / 2, true, kCoarseBox);
    f.scene.bodies[0].desc.position = {3, 2, -1};
    f.scene.bodies[0].desc.dragCoefficient = 1;  // the test turns drag and damping off itself
    f.scene.bodies[0].desc.linearDamping = 0.5;
    Result<HeaveDecayTest> decay = runHeaveDecayTest(f.scene, 0, 0.02, 3);
    ASSERT_TRUE(decay.ok()) << decay.error().message;
    EXPECT_NEAR(decay->stiffness, kDensity * kGravity, 0.01 * kDensity * kGravity);
    // Interpolated in 12 stored frequencies against the panel solution itself.
    Result<RestRadiationSurface> surface = restRadiationSurface(
        f.scene.bodies[0], kCoarseBox, f.scene.medium, f.scene.simulation.gravity);
    ASSERT_TRUE(surface.ok());
    const test::DecayFigures panels = test::predictedHeaveDecay(
        *surface->solver, f.radiation->restVolume * kDensity, decay->stiffness);
    std::printf(
        "  decay test: period %.4f s (predicted %.4f, panels %.4f), log decrement %.4f (predicted "
        "%.4f, "
        "panels %.4f)\n",
        decay->measured.period, decay->predicted.period, panels.period,
        decay->measured.logDecrement, decay->predicted.logDecrement, panels.logDecrement);
    EXPECT_NEAR(decay->predicted.period, panels.period, 0.01 * panels.period);
    EXPECT_NEAR(decay->predicted.logDecrement, panels.logDecrement, 0.05 * panels.logDecrement);
    EXPECT_NEAR(decay->measured.period, decay->predicted.period, 0.05 * decay->predicted.period);
    EXPECT_NEAR(decay->measured.logDecrement, decay->predicted.logDecrement,
                0.06 * decay->predicted.logDecrement);
    EXPECT_NEAR(decay->offset.front(), -0.02, 1e-3);  // released 2 cm below rest

    Scene plain = f.scene;
    plain.bodies[0].radiation.reset();
    Result<HeaveDecayTest> refused = runHeaveDecayTest(plain, 0);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("no radiation computed"), std::string::npos)
        << refused.error().message;
}

TEST(WorldRadiation, DroppedLightBoxSettlesSoonerThanWithoutIt) {
    // The density-250 cube released 0.35 m above its rest height leaves and re-enters the water
    // (the added mass and memory follow the submerged share): energy must still only fall, and it
    // must settle well before the run without radiation does. Both keep the default drag and
    // linear-damping stand-in, as a project gets them (upright, this cube is unstable in roll: it
    // capsizes to about 40 degrees, and radiation alone does not damp the drift that follows).
    Floating with = floating(makeBox({1, 1, 1}), 250, true, kCoarseBox);
    BodyDesc& desc = with.scene.bodies[0].desc;
    desc.dragCoefficient = BodyDesc{}.dragCoefficient;
    desc.linearDamping = BodyDesc{}.linearDamping;
    desc.angularDamping = BodyDesc{}.angularDamping;
    desc.position = {0, with.radiation->restHeight + 0.35, 0};
    Floating without = with;
    without.scene.bodies[0].desc.radiation.reset();
    without.scene.bodies[0].radiation = nullptr;
    const double rest = with.radiation->restHeight;
    std::unique_ptr<World> radiating = test::fastWorldOrFail(with.scene);
    std::unique_ptr<World> bare = test::fastWorldOrFail(without.scene);
    ASSERT_TRUE(radiating && bare);
    const double scale = 250 * kGravity * 0.35;
    // The sanitized build (about twenty times slower) runs the drop for 5 s with radiation and
    // checks the energy only; where and when it settles is left to the normal build.
    if (test::kSanitizedBuild) {
        EXPECT_LT(run(*radiating, rest, 5, scale).worstEnergyRise, 1e-9);
        return;
    }
    const Record r = run(*radiating, rest, 60, scale);
    // The issue measured about 60 s without: 90 s to see it happen.
    const Record b = run(*bare, rest, 90, scale);
    std::printf(
        "  dropped density-250 cube settles (|v| < 1 mm/s) after %.2f s with radiation, %.2f s "
        "without "
        "(speed at the end: %.2e m/s at 60 s, %.2e m/s at 90 s)\n",
        r.settleTime, b.settleTime, r.finalSpeed, b.finalSpeed);
    EXPECT_LT(r.worstEnergyRise, 1e-9);
    EXPECT_GT(r.settleTime, 1.0);
    // Measured: 53.8 s against 72 s; the roll and drift after capsizing, which radiation computed
    // upright hardly damps, set both times.
    EXPECT_LT(r.settleTime, 0.9 * b.settleTime);
    EXPECT_LT(b.finalSpeed, 1e-3);  // so that b.settleTime is when it settled
    EXPECT_LT(r.finalSpeed, 1e-3);
}

TEST(WorldRadiation, AddedMassIsInTheMassMatrixAndOffWithoutIt) {
    // On: the body carries the infinite-frequency added mass, and its velocity is the one asked
    // for. Off (the same settings present but disabled): nothing of it.
    const TriangleMesh cube = makeBox({1, 1, 1});
    for (const bool on : {true, false}) {
        RadiationDesc desc = kCoarseBox;
        desc.enabled = on;
        Floating f = floating(cube, 500, true, desc);
        f.scene.bodies[0].desc.radiation = desc;
        f.scene.bodies[0].desc.position = {0, f.radiation->restHeight, 0};
        f.scene.bodies[0].desc.velocity = {0.1, -0.2, 0.05};
        std::unique_ptr<World> world = test::fastWorldOrFail(f.scene);
        ASSERT_TRUE(world);
        const SimulatedBody& b = world->bodies()[0];
        EXPECT_LT((linearVelocity(b.state, b.mass) - Eigen::Vector3d(0.1, -0.2, 0.05)).norm(),
                  1e-12);
        if (on) {
            ASSERT_NE(world->radiation(0), nullptr);
            EXPECT_NEAR(b.mass.addedMass(1, 1), f.radiation->addedMassInfinity(kHeaveY, kHeaveY),
                        1e-9);
            EXPECT_GT(b.mass.addedMass(1, 1), 0.1 * b.mass.mass);
        } else {
            EXPECT_EQ(world->radiation(0), nullptr);
            EXPECT_EQ(b.mass.addedMass, Eigen::Matrix3d::Zero());
        }
    }
}

TEST(WorldRadiation, OnWithoutComputedCoefficientsIsRefused) {
    Floating f = floating(makeBox({1, 1, 1}), 500, true, kCoarseBox);
    f.scene.bodies[0].radiation = nullptr;
    Result<std::unique_ptr<World>> world = World::create(f.scene, createReferenceBackend());
    ASSERT_FALSE(world.ok());
    EXPECT_NE(world.error().message.find("radiation"), std::string::npos) << world.error().message;
    EXPECT_NE(world.error().message.find("body 'body'"), std::string::npos)
        << world.error().message;
}

TEST(WorldRadiation, ABodyThatDoesNotFloatIsRefused) {
    BodyDesc body;
    body.name = "stone";
    body.mesh = "generated";
    body.textureSize = 32;
    body.material.density = 2500;
    const SceneBody stone = test::bodyOrFail(body, makeBox({1, 1, 1}));
    Result<BodyRadiation> r = computeBodyRadiation(stone, {}, MediumDesc{}, {0, -kGravity, 0});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("does not float"), std::string::npos) << r.error().message;
    RadiationDesc tiny;
    tiny.panelEdge = 1e-4;
    body.material.density = 500;
    const SceneBody box = test::bodyOrFail(body, makeBox({1, 1, 1}));
    Result<BodyRadiation> many = computeBodyRadiation(box, tiny, MediumDesc{}, {0, -kGravity, 0});
    ASSERT_FALSE(many.ok());
    EXPECT_EQ(many.error().kind, ErrorKind::limit);
    EXPECT_NE(many.error().message.find("kMaxRadiationPanels"), std::string::npos)
        << many.error().message;
}

}  // namespace
}  // namespace test_world_radiation
}  // namespace plimsoll
