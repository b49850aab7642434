// Radiation on by default (docs/radiation.md "On by default"): a project body that floats gets
// added mass and radiation damping without asking, with the lower stand-in damping; a project
// that turns it off gets the old behaviour back; a body off its upright rest attitude keeps a
// passive approximation; and a light flat box dropped from half a metre settles within 10 s.
#include "plimsoll/project/project.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/scene_radiation.h"
#include "plimsoll/scene/world.h"

#include "test_support.h"
#include "world_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>

namespace plimsoll {
namespace test_radiation_default {
namespace {

constexpr double kGravity = 9.81;

/// The fastest any point of body 0 moves, bounded by |v| + |w| R (m/s).
double pointSpeed(const World& world) {
    const SimulatedBody& b = world.bodies()[0];
    return linearVelocity(b.state, b.mass).norm() +
           angularVelocity(b.state, b.mass).norm() * b.boundingRadius;
}

/// The last time (s) body 0's pointSpeed was at least `threshold`, running `seconds`; infinity
/// when it still was at the end, 0 when it never was.
double settleTime(World& world, double seconds, double threshold = 1e-3) {
    double last = 0;
    const long frames = std::lround(seconds / world.scene().simulation.timeStep);
    for (long f = 0; f < frames; ++f) {
        EXPECT_TRUE(world.advanceFrame().ok());
        if (pointSpeed(world) >= threshold) last = world.time();
    }
    return pointSpeed(world) >= threshold ? std::numeric_limits<double>::infinity() : last;
}

/// A flat box 2 x 0.5 x 2 m of `density` in fresh water, released with its centre `drop` above
/// its rest height, every setting the default; radiation computed as the loader computes it
/// when `withRadiation`, and turned off ("radiation": false) otherwise.
Scene droppedBox(double density, double drop, bool withRadiation,
                 const Eigen::Vector3d& rotationDeg = {}) {
    BodyDesc desc;
    desc.name = "flat box";
    desc.mesh = "generated";
    desc.textureSize = 128;
    desc.material.density = density;
    if (!withRadiation) desc.radiation = RadiationDesc{.enabled = false};
    Scene scene;
    scene.water = WaterModel::flat(0.0);
    scene.simulation.gravity = {0, -kGravity, 0};
    SceneBody body = test::bodyOrFail(desc, makeBox({2, 0.5, 2}));
    // Rest: draft 0.5 * density / 1000, the centre at 0.25 - draft.
    const double rest = 0.25 - 0.5 * density / scene.medium.density;
    body.desc.position = {0, rest + drop, 0};
    body.desc.rotationDegrees = rotationDeg;
    if (withRadiation) {
        EXPECT_FALSE(defaultRadiationInapplicable(body, scene.medium));
        // Computed once per density: the solve (about 10 s) does not depend on the release.
        static std::map<double, std::shared_ptr<const BodyRadiation>> solved;
        std::shared_ptr<const BodyRadiation>& r = solved[density];
        if (!r) {
            Result<BodyRadiation> computed =
                computeBodyRadiation(body, {}, scene.medium, scene.simulation.gravity);
            EXPECT_TRUE(computed.ok()) << (computed.ok() ? "" : computed.error().message);
            if (computed) r = std::make_shared<const BodyRadiation>(std::move(*computed));
        }
        body.radiation = r;
    }
    scene.bodies.push_back(std::move(body));
    return scene;
}

TEST(RadiationDefault, FlatLightBoxDroppedHalfAMetreSettlesWithinTenSeconds) {
    // The box: a quarter of water's density, dropped from 0.5 m, the default settings.
    std::unique_ptr<World> on = test::fastWorldOrFail(droppedBox(250, 0.5, true));
    std::unique_ptr<World> off = test::fastWorldOrFail(droppedBox(250, 0.5, false));
    ASSERT_TRUE(on && off);
    ASSERT_NE(on->radiation(0), nullptr);
    EXPECT_EQ(off->radiation(0), nullptr);
    const double withRadiation = settleTime(*on, test::kSanitizedBuild ? 10.5 : 20);
    if (test::kSanitizedBuild) {
        EXPECT_LT(withRadiation, 10.0);
        return;
    }
    const double without = settleTime(*off, 60);
    std::printf(
        "  flat box of density 250 dropped 0.5 m: |v| + |w| R below 1 mm/s after %.2f s by "
        "default, "
        "%.2f s with radiation off (the old defaults)\n",
        withRadiation, without);
    EXPECT_GT(withRadiation, 0.5);
    EXPECT_LT(withRadiation, 10.0);
    EXPECT_LT(withRadiation, without);
}

TEST(RadiationDefault, TheStandInDampingFollowsRadiationUnlessGiven) {
    // Radiating by default: the lower stand-in; turned off: the old 0.5; given: as given either
    // way.
    std::unique_ptr<World> on = test::fastWorldOrFail(droppedBox(500, 0, true));
    std::unique_ptr<World> off = test::fastWorldOrFail(droppedBox(500, 0, false));
    ASSERT_TRUE(on && off);
    EXPECT_EQ(on->bodies()[0].linearDamping, kRadiatingHorizontalDamping);
    EXPECT_EQ(on->bodies()[0].verticalDamping, kRadiatingVerticalDamping);
    EXPECT_EQ(on->bodies()[0].angularDamping, kRadiatingAngularDamping);
    EXPECT_EQ(off->bodies()[0].linearDamping, kStandInDamping);
    EXPECT_EQ(off->bodies()[0].verticalDamping, kStandInDamping);
    EXPECT_EQ(off->bodies()[0].angularDamping, kStandInDamping);
    EXPECT_EQ(off->bodies()[0].mass.addedMass, Eigen::Matrix3d::Zero());
    Scene given = droppedBox(500, 0, true);
    given.bodies[0].desc.linearDamping = 0.3;
    given.bodies[0].desc.angularDamping = 0.0;
    std::unique_ptr<World> world = test::fastWorldOrFail(given);
    ASSERT_TRUE(world);
    EXPECT_EQ(world->bodies()[0].linearDamping, 0.3);
    EXPECT_EQ(world->bodies()[0].verticalDamping, 0.3);
    EXPECT_EQ(world->bodies()[0].angularDamping, 0.0);
    // A hand-built scene whose body has no radiation computed runs without, as before.
    Scene bare = droppedBox(500, 0, true);
    bare.bodies[0].radiation = nullptr;
    std::unique_ptr<World> plain = test::fastWorldOrFail(bare);
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->radiation(0), nullptr);
    EXPECT_EQ(plain->bodies()[0].linearDamping, kStandInDamping);
    EXPECT_EQ(plain->bodies()[0].verticalDamping, kStandInDamping);
}

TEST(RadiationDefault, OffItsUprightRestAttitudeTheDampingStaysPassive) {
    // Rolled 60 degrees (this box's upright rest is stable; capsized halfway, its coefficients
    // act in body axes, the approximation docs/radiation.md states) and upside down: with no drag
    // and no stand-in, the energy (the memory's included) never rises from frame to frame and
    // most of it is gone after 20 s.
    for (const double roll : {60.0, 180.0}) {
        Scene scene = droppedBox(500, 0.1, true, {roll, 0, 0});
        scene.bodies[0].desc.dragCoefficient = 0;
        scene.bodies[0].desc.linearDamping = 0;
        scene.bodies[0].desc.angularDamping = 0;
        scene.simulation.timeStep = 1.0 / 240;
        std::unique_ptr<World> world = test::fastWorldOrFail(scene);
        ASSERT_TRUE(world);
        ASSERT_NE(world->radiation(0), nullptr);
        const double start = world->mechanicalEnergy(0);
        double previous = start, worstRise = -std::numeric_limits<double>::infinity(),
               lowest = start;
        const long frames =
            std::lround((test::kSanitizedBuild ? 3.0 : 20.0) / scene.simulation.timeStep);
        for (long f = 0; f < frames; ++f) {
            ASSERT_TRUE(world->advanceFrame().ok());
            const double e = world->mechanicalEnergy(0);
            ASSERT_TRUE(std::isfinite(e));
            worstRise = std::max(worstRise, e - previous);
            lowest = std::min(lowest, e);
            previous = e;
        }
        std::printf(
            "  rolled %.0f deg: worst energy rise in a frame %.3g J of %.3g J at the start; %.1f%% "
            "left\n",
            roll, worstRise, start - lowest, 100 * (previous - lowest) / (start - lowest));
        // The energy relative to its lowest (the rest attitude it ends at).
        EXPECT_LT(worstRise, 1e-3 * (start - lowest) + 1e-9) << roll;
        if (!test::kSanitizedBuild) EXPECT_LT(previous - lowest, 0.05 * (start - lowest)) << roll;
    }
}

/// Body 0 of sample project `name` on flat water (the buoy's waves would keep it moving):
/// when it settles with the project's defaults and with "radiation": false.
void expectSettlesAtLeastAsFast(const std::string& name, double seconds) {
    Result<Project> project = loadProject(std::filesystem::path(PLIMSOLL_SOURCE_DIR) / "projects" /
                                          (name + ".plim.json"));
    ASSERT_TRUE(project.ok()) << project.error().message;
    project->water = WaterModel::flat(project->water.level);
    Project off = *project;
    for (BodyDesc& b : off.bodies) b.radiation = RadiationDesc{.enabled = false};
    std::unique_ptr<World> withDefaults = test::fastWorldOrFail(test::sceneOrFail(*project));
    std::unique_ptr<World> old = test::fastWorldOrFail(test::sceneOrFail(off));
    ASSERT_TRUE(withDefaults && old);
    const double now = settleTime(*withDefaults, seconds), before = settleTime(*old, seconds);
    std::printf(
        "  %s: settles (|v| + |w| R < 1 mm/s) after %.2f s by default (radiation %s), %.2f s with "
        "the old "
        "defaults\n",
        name.c_str(), now, withDefaults->radiation(0) ? "on" : "off", before);
    EXPECT_LE(now, before + 1e-9) << name;
}

TEST(RadiationDefault, SampleBodiesSettleAtLeastAsFastAsWithTheOldDefaults) {
    if (test::kSanitizedBuild) GTEST_SKIP() << "minutes of simulated time";
    for (const char* name : {"box_half_draft", "neutral_ball", "heavy_side_ball", "buoy", "plush",
                             "damaged_boat", "balloon"}) {
        expectSettlesAtLeastAsFast(name, 30);
    }
}

}  // namespace
}  // namespace test_radiation_default
}  // namespace plimsoll
