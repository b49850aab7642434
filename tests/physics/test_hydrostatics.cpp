// Hydrostatics against closed forms: a box's draft, KB, BM and GM (exact clip and texel sums),
// its GZ against the wall-sided formula, a sphere's vanishing GZ, the free-surface loss of a
// box compartment, and the sign of GM against what the simulation does with the same box.
#include "plimsoll/physics/hydrostatics.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/geometry/box.h"
#include "plimsoll/graph/graph.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/scene_hydrostatics.h"
#include "plimsoll/scene/world.h"

#include "test_support.h"
#include "world_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace plimsoll {
namespace test_hydrostatics {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

/// A box of length L along x, height H along y and beam W along z, of uniform density rho_b,
/// floating upright in water of density 1000: the closed forms of naval architecture.
struct FloatingBox {
    double length, height, beam, density;

    Eigen::Vector3d size() const { return {length, height, beam}; }
    double draft() const { return height * density / 1000.0; }
    double displacement() const { return length * beam * draft(); }
    double kb() const { return draft() / 2; }
    double kg() const { return height / 2; }
    double bmTransverse() const { return beam * beam / (12 * draft()); }
    double bmLongitudinal() const { return length * length / (12 * draft()); }
    double gmTransverse() const { return kb() + bmTransverse() - kg(); }
    double gmLongitudinal() const { return kb() + bmLongitudinal() - kg(); }
    /// The wall-sided formula, valid while neither the deck edge nor the bilge leaves its wall.
    double wallSidedArm(double heel) const {
        const double t = std::tan(heel);
        return std::sin(heel) * (gmTransverse() + bmTransverse() / 2 * t * t);
    }
    double wallSidedLimit() const {
        const double deckEdge = std::atan((height - draft()) / (beam / 2));
        return std::min(deckEdge, std::atan(draft() / (beam / 2)));  // or the bilge
    }
    /// The box's mass at its centre (the box is centred on the origin).
    HydrostaticBody body() const {
        return {density * length * height * beam, Eigen::Vector3d::Zero(), {}, {}};
    }
};

const FloatingBox kBox{3.0, 1.0, 2.0, 400.0};

HydrostaticsResult exactOrFail(const TriangleMesh& mesh, const HydrostaticBody& body,
                               const HydrostaticsSettings& settings = {}) {
    Result<HydrostaticsResult> r = hydrostaticsExact(mesh, body, settings);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value() : HydrostaticsResult{};
}

HydrostaticsResult texturesOrFail(const SurfaceTextures& textures, const HydrostaticBody& body,
                                  const HydrostaticsSettings& settings = {}) {
    Result<HydrostaticsResult> r = hydrostaticsFromTextures(textures, body, settings);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value() : HydrostaticsResult{};
}

void expectBoxFigures(const FloatingBox& box, const HydrostaticsResult& r, double relative) {
    auto near = [&](double got, double want, const char* what) {
        EXPECT_NEAR(got, want, relative * std::abs(want)) << what << " (" << r.gz.size() << ")";
    };
    near(r.displacement, box.displacement(), "displacement");
    near(r.draft, box.draft(), "draft");
    near(r.kb, box.kb(), "KB");
    near(r.kg, box.kg(), "KG");
    near(r.waterplaneArea, box.length * box.beam, "waterplane area");
    near(r.bmTransverse, box.bmTransverse(), "BM transverse");
    near(r.bmLongitudinal, box.bmLongitudinal(), "BM longitudinal");
    near(r.gmTransverse, box.gmTransverse(), "GM transverse");
    near(r.gmLongitudinal, box.gmLongitudinal(), "GM longitudinal");
    EXPECT_NEAR(r.heelDegrees, 0.0, 1e-9);
    EXPECT_NEAR(r.trimDegrees, 0.0, 1e-9);
    EXPECT_NEAR(r.centerOfFlotation.x(), 0.0, relative * box.length);
    EXPECT_NEAR(r.centerOfFlotation.z(), 0.0, relative * box.beam);
    EXPECT_NEAR(r.centerOfFlotation.y(), box.draft() - box.height / 2, relative * box.height);
}

TEST(Hydrostatics, BoxMatchesItsClosedFormsExactly) {
    expectBoxFigures(kBox, exactOrFail(makeBox(kBox.size()), kBox.body()), 1e-6);
}

TEST(Hydrostatics, BoxMatchesItsClosedFormsFromTexturesAt128) {
    const SurfaceTextures textures = test::bakeOrFail(makeBox(kBox.size()), 128);
    expectBoxFigures(kBox, texturesOrFail(textures, kBox.body()), 1e-3);
}

TEST(Hydrostatics, BoxRightingArmFollowsTheWallSidedFormula) {
    const TriangleMesh mesh = makeBox(kBox.size());
    HydrostaticsSettings settings;
    settings.gzStepDegrees = 1.0;
    const HydrostaticsResult exact = exactOrFail(mesh, kBox.body(), settings);
    const HydrostaticsResult textures =
        texturesOrFail(test::bakeOrFail(mesh, 128), kBox.body(), settings);
    ASSERT_EQ(exact.gz.size(), 181u);
    ASSERT_EQ(textures.gz.size(), 181u);
    int checked = 0;
    for (std::size_t i = 0; i < exact.gz.size(); ++i) {
        const double heel = exact.gz[i].heelDegrees * kDegree;
        if (heel > kBox.wallSidedLimit()) break;
        EXPECT_NEAR(exact.gz[i].arm, kBox.wallSidedArm(heel), 1e-9 * kBox.beam) << heel / kDegree;
        EXPECT_NEAR(textures.gz[i].arm, kBox.wallSidedArm(heel), 1e-3 * kBox.beam)
            << heel / kDegree;
        EXPECT_NEAR(exact.gz[i].trimDegrees, 0.0, 1e-9);
        ++checked;
    }
    EXPECT_GE(checked, 20);
    // Upside down the box floats as upright: GZ is zero at 180 degrees, and (the section wider
    // than its freeboard) it rights all the way to where the curve crosses zero once.
    EXPECT_NEAR(exact.gz.back().arm, 0.0, 1e-9);
    EXPECT_GT(exact.vanishingStabilityDegrees, kBox.wallSidedLimit() / kDegree);
    EXPECT_LT(exact.vanishingStabilityDegrees, 180.0);
    EXPECT_NEAR(textures.vanishingStabilityDegrees, exact.vanishingStabilityDegrees, 0.5);
}

TEST(Hydrostatics, SphereHasNoRightingArmAtAnyHeel) {
    const double radius = 0.5;
    const TriangleMesh mesh = makeUvSphere(radius, 64, 32);
    const MassProperties solid = exactSolidMassProperties(mesh, 600.0);
    HydrostaticBody body{solid.mass, solid.centerOfMass, {}, {}};
    HydrostaticsSettings settings;
    settings.gzStepDegrees = 10.0;
    const SurfaceTextures textures = test::bakeOrFail(mesh, 128);
    for (const HydrostaticsResult& r :
         {exactOrFail(mesh, body, settings), texturesOrFail(textures, body, settings)}) {
        ASSERT_EQ(r.gz.size(), 19u);
        for (const RightingArm& p : r.gz) {
            EXPECT_NEAR(p.arm, 0.0, 1e-3 * radius)
                << hydrostaticsMethodName(r.method) << " at " << p.heelDegrees;
        }
        // A sphere's metacentre is its centre: GM = 0 with G there.
        EXPECT_NEAR(r.gmTransverse, 0.0, 2e-3 * radius) << hydrostaticsMethodName(r.method);
        EXPECT_NEAR(r.kb + r.bmTransverse, radius, 2e-3 * radius);
    }
}

TEST(Hydrostatics, FreeSurfaceOfAHalfFilledBoxCompartment) {
    WaterGraph graph;
    GraphNode tank;
    tank.id = "tank";
    tank.boxSize = Eigen::Vector3d(1.0, 0.5, 0.8);
    tank.capacity = tank.boxSize.prod();
    tank.water = 0.5 * tank.capacity;
    graph.nodes.push_back(tank);
    GraphNode full = tank;
    full.id = "full";
    full.water = full.capacity;  // a full compartment has no free surface
    graph.nodes.push_back(full);
    const std::vector<FreeSurface> surfaces = graphFreeSurfaces(graph, 1000.0);
    ASSERT_EQ(surfaces.size(), 1u);
    EXPECT_NEAR(surfaces[0].inertiaAboutX, 1.0 * 0.8 * 0.8 * 0.8 / 12, 1e-15);
    EXPECT_NEAR(surfaces[0].inertiaAboutZ, 0.8 * 1.0 * 1.0 * 1.0 / 12, 1e-15);

    HydrostaticBody body = kBox.body();
    body.freeSurfaces = surfaces;
    const HydrostaticsResult r = exactOrFail(makeBox(kBox.size()), body);
    EXPECT_NEAR(r.freeSurfaceLossTransverse, surfaces[0].inertiaAboutX / kBox.displacement(),
                1e-12);
    EXPECT_NEAR(r.freeSurfaceLossLongitudinal, surfaces[0].inertiaAboutZ / kBox.displacement(),
                1e-12);

    // A sphere node half full: the surface is its great circle, pi r^4 / 4.
    GraphNode ball;
    ball.id = "ball";
    ball.capacity = 4.0 / 3.0 * std::numbers::pi * 0.125;  // r = 0.5
    ball.water = 0.5 * ball.capacity;
    const std::vector<FreeSurface> circle = graphFreeSurfaces(WaterGraph{{ball}, {}}, 1000.0);
    ASSERT_EQ(circle.size(), 1u);
    EXPECT_NEAR(circle[0].inertiaAboutX, std::numbers::pi * std::pow(0.5, 4) / 4, 1e-12);
}

TEST(Hydrostatics, SinkingBodyIsRefused) {
    const FloatingBox heavy{1.0, 1.0, 1.0, 1200.0};
    Result<HydrostaticsResult> r = hydrostaticsExact(makeBox(heavy.size()), heavy.body(), {});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, ErrorKind::invalidArgument);
    EXPECT_NE(r.error().message.find("sinks"), std::string::npos) << r.error().message;
}

TEST(Hydrostatics, SceneBodyFloatsWithItsGraphWater) {
    WaterGraph graph;
    GraphNode tank;
    tank.id = "tank";
    tank.position = Eigen::Vector3d(0.5, -0.2, 0.0);
    tank.boxSize = Eigen::Vector3d(0.8, 0.4, 1.0);
    tank.capacity = tank.boxSize.prod();
    tank.water = 0.25 * tank.capacity;
    graph.nodes.push_back(tank);
    BodyDesc desc;
    desc.name = "box";
    desc.mesh = "box (generated)";
    desc.textureSize = 64;
    desc.material.density = kBox.density;
    desc.waterGraph = WaterGraphDesc{.graph = "tank.graph.json"};
    Result<SceneBody> body =
        bakeSceneBody(desc, {.mesh = std::make_shared<const TriangleMesh>(makeBox(kBox.size())),
                             .waterGraph = std::make_shared<const WaterGraph>(graph)});
    ASSERT_TRUE(body.ok()) << body.error().message;
    Result<FloatingBody> floating = floatingBodyOf(*body, MediumDesc{});
    ASSERT_TRUE(floating.ok()) << floating.error().message;

    const double water = 1000.0 * tank.water;  // kg, the medium's density
    const double hull = body->mass->mass;
    EXPECT_NEAR(floating->graphWater, tank.water, 1e-15);
    EXPECT_NEAR(floating->body.mass, hull + water, 1e-9);
    const Eigen::Vector3d center =
        (hull * body->mass->centerOfMass + water * tank.position) / (hull + water);
    EXPECT_LT((floating->body.centerOfMass - center).norm(), 1e-12);
    ASSERT_EQ(floating->body.freeSurfaces.size(), 1u);

    // The loaded box floats deeper by the water's mass and heels towards the tank.
    const HydrostaticsResult r = exactOrFail(makeBox(kBox.size()), floating->body);
    EXPECT_NEAR(r.displacement, (hull + water) / 1000.0, 1e-12);
    EXPECT_NEAR(r.freeSurfaceLossTransverse, 0.8 * 1.0 * 1.0 * 1.0 / 12 / r.displacement, 1e-12);
    EXPECT_LT(r.trimDegrees, -0.1);  // the tank sits at +x: that end goes down
    EXPECT_NEAR(r.heelDegrees, 0.0, 1e-9);
}

/// Tilt of the body's y axis from the vertical after `seconds` in a World, started at `heel`.
double tiltAfter(const FloatingBox& box, double heelDegrees, double seconds) {
    BodyDesc desc;
    desc.name = "box";
    desc.mesh = "box (generated)";
    desc.textureSize = 64;
    desc.material.density = box.density;
    desc.position = Eigen::Vector3d(0, box.height / 2 - box.draft(), 0);
    desc.rotationDegrees = Eigen::Vector3d(heelDegrees, 0, 0);
    Scene scene;
    scene.bodies.push_back(test::bodyOrFail(desc, makeBox(box.size())));
    scene.water = WaterModel::flat(0.0);
    std::unique_ptr<World> world = test::worldOrFail(std::move(scene));
    if (!world) return std::nan("");
    const int frames = static_cast<int>(std::round(seconds / world->scene().simulation.timeStep));
    for (int i = 0; i < frames; ++i) {
        if (!world->advanceFrame().ok()) return std::nan("");
    }
    const Eigen::Vector3d up = world->bodies()[0].state.orientation * Eigen::Vector3d::UnitY();
    return std::acos(std::clamp(up.y(), -1.0, 1.0)) / kDegree;
}

TEST(Hydrostatics, NegativeGmCapsizesInTheSimulationAndPositiveRights) {
    const FloatingBox tall{1.0, 2.0, 1.0, 500.0};  // KB 0.5 + BM 1/12 < KG 1
    const FloatingBox wide{2.0, 1.0, 2.0, 500.0};  // KB 0.25 + BM 2/3 > KG 0.5
    const HydrostaticsResult tallStatics = exactOrFail(makeBox(tall.size()), tall.body());
    const HydrostaticsResult wideStatics = exactOrFail(makeBox(wide.size()), wide.body());
    EXPECT_NEAR(tallStatics.gmTransverse, tall.gmTransverse(), 1e-6);
    EXPECT_LT(tallStatics.gmTransverse, 0.0);
    EXPECT_GT(wideStatics.gmTransverse, 0.0);
    // The upright tall box rights no heel at all; the wide one rights every small one.
    EXPECT_NEAR(tallStatics.vanishingStabilityDegrees, 0.0, 1e-9);
    EXPECT_LT(tallStatics.gz[1].arm, 0.0);
    EXPECT_GT(wideStatics.gz[1].arm, 0.0);

    EXPECT_GT(tiltAfter(tall, 3.0, 6.0), 30.0);
    EXPECT_LT(tiltAfter(wide, 10.0, 10.0), 2.0);
}

}  // namespace
}  // namespace test_hydrostatics
}  // namespace plimsoll
