// The exact planar-water buoyancy reference against answers reached another way: analytic
// caps of a ball, prisms of a box, a hand-built solid cut through its vertices, the shared
// meshes' README values (exact rational arithmetic), and the identities flat water must keep
// (pressure integral = Archimedes, part below + part above = whole). Also
// Pose::fromEulerDegrees.
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/physics/pose.h"
#include "plimsoll/samples/primitives.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <utility>

namespace plimsoll {
namespace test_buoyancy_exact {
namespace {

using Eigen::Vector3d;

constexpr double kPi = std::numbers::pi;

BuoyancyResult evaluate(const TriangleMesh& mesh, const Pose& pose, const Vector3d& centerOfMass,
                        double waterLevel) {
    BodyFrame frame;
    frame.pose = pose;
    frame.centerOfMass = centerOfMass;
    return evaluateBuoyancyExact(mesh, frame, waterLevel, FluidSettings{});
}

double rhoG() {
    const FluidSettings fluid;
    return fluid.density * fluid.gravity;  // N/m^3
}

/// The mesh reflected in the plane y = 0, winding reversed so it stays outward: its part below
/// y = -h is the original's part above y = h.
TriangleMesh mirroredInY(TriangleMesh mesh) {
    for (Vector3d& p : mesh.positions) p.y() = -p.y();
    for (Triangle& t : mesh.triangles) std::swap(t[1], t[2]);
    return mesh;
}

/// On flat water the pressure integral over the wetted surface is Archimedes' force acting
/// through the centre of buoyancy: the same physics, so they agree to rounding. leverArm (m)
/// sizes the torque tolerance.
void expectPressureMatchesArchimedes(const BuoyancyResult& r, double leverArm) {
    EXPECT_LE((r.pressureForce - r.force).norm(), 1e-9 * r.force.norm());
    EXPECT_LE((r.pressureTorque - r.torque).norm(), 1e-9 * r.force.norm() * leverArm);
}

void expectDry(const BuoyancyResult& r, const Vector3d& worldCenterOfMass) {
    EXPECT_EQ(r.submergedVolume, 0.0);
    EXPECT_EQ(r.centerOfBuoyancy, worldCenterOfMass);
    EXPECT_EQ(r.force, Vector3d::Zero());
    EXPECT_EQ(r.torque, Vector3d::Zero());
    EXPECT_EQ(r.pressureForce, Vector3d::Zero());
    EXPECT_EQ(r.pressureTorque, Vector3d::Zero());
    EXPECT_EQ(r.wettedArea, 0.0);
}

/// The octahedron with vertices at distance 1 on the axes, except +x moved to `plusX`; faces
/// wound outward (every face plane misses the origin, which lies inside).
TriangleMesh octahedron(const Vector3d& plusX) {
    TriangleMesh mesh;
    mesh.source = "test:octahedron";
    mesh.positions = {plusX, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (std::uint32_t x : {0u, 1u}) {
        for (std::uint32_t y : {2u, 3u}) {
            for (std::uint32_t z : {4u, 5u}) {
                Triangle t{x, y, z};
                const Vector3d& a = mesh.positions[x];
                const Vector3d& b = mesh.positions[y];
                const Vector3d& c = mesh.positions[z];
                if ((b - a).cross(c - a).dot(a + b + c) < 0.0) std::swap(t[1], t[2]);
                mesh.triangles.push_back(t);
            }
        }
    }
    return mesh;
}

// ---------------------------------------------------------------------------------------------
// Pose::fromEulerDegrees

TEST(PoseFromEulerDegrees, NinetyAboutXTurnsYIntoZ) {
    const Pose pose = Pose::fromEulerDegrees(Vector3d::Zero(), {90, 0, 0});
    EXPECT_LT((pose.rotation * Vector3d::UnitY() - Vector3d::UnitZ()).norm(), 1e-15);
    EXPECT_LT((pose.rotation * Vector3d::UnitZ() + Vector3d::UnitY()).norm(), 1e-15);
    EXPECT_LT((pose.rotation * Vector3d::UnitX() - Vector3d::UnitX()).norm(), 1e-15);
}

TEST(PoseFromEulerDegrees, RotatesAboutXThenYThenZAndTranslates) {
    const Vector3d degrees(30, -50, 70);
    const Vector3d position(1.5, -2, 3);
    const Pose pose = Pose::fromEulerDegrees(position, degrees);
    // Hand-written fixed-axis rotations, applied one after the other: x first.
    const auto about = [](int axis, double deg) {
        const double c = std::cos(deg * kPi / 180.0);
        const double s = std::sin(deg * kPi / 180.0);
        Eigen::Matrix3d m;
        if (axis == 0) m << 1, 0, 0, 0, c, -s, 0, s, c;
        if (axis == 1) m << c, 0, s, 0, 1, 0, -s, 0, c;
        if (axis == 2) m << c, -s, 0, s, c, 0, 0, 0, 1;
        return m;
    };
    const Vector3d v(0.3, -1.2, 0.7);
    const Vector3d stepwise = about(2, 70) * (about(1, -50) * (about(0, 30) * v));
    EXPECT_LT((pose.rotation * v - stepwise).norm(), 1e-14);
    EXPECT_LT((pose.apply(v) - (stepwise + position)).norm(), 1e-14);
    const Eigen::Matrix3d composed = (Eigen::AngleAxisd(70 * kPi / 180, Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(-50 * kPi / 180, Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(30 * kPi / 180, Vector3d::UnitX()))
                                         .toRotationMatrix();
    EXPECT_LT((pose.rotation - composed).norm(), 1e-14);
    // The other order is a different rotation, so the test above does tell them apart.
    const Vector3d reversed = about(0, 30) * (about(1, -50) * (about(2, 70) * v));
    EXPECT_GT((pose.rotation * v - reversed).norm(), 0.1);
    EXPECT_LT((pose.rotation.transpose() * pose.rotation - Eigen::Matrix3d::Identity()).norm(),
              1e-15);
}

// ---------------------------------------------------------------------------------------------
// Ball: analytic caps (within the tessellation error) and exact identities

TEST(BuoyancyExact, SphereCapsMatchTheAnalyticCap) {
    const double r = 0.5;  // m
    const TriangleMesh sphere = makeUvSphere(r, 256, 128);
    const double ball = 4.0 / 3.0 * kPi * r * r * r;  // m^3
    // A turn about y leaves every height unchanged, so the analytic cap still applies.
    const Pose pose = Pose::fromEulerDegrees({3, -2, 7}, {0, 30, 0});
    double worstVolume = 0;
    double worstHeight = 0;
    for (int step = 0; step <= 20; ++step) {
        const double d = 2.0 * r * step / 20.0;  // depth of the lowest point, m
        const BuoyancyResult result = evaluate(sphere, pose, Vector3d::Zero(), -2.0 - r + d);
        if (step == 0) {
            expectDry(result, pose.translation);
            continue;
        }
        SCOPED_TRACE(d);
        const double cap = kPi * d * d * (3 * r - d) / 3;  // m^3
        // The cap's centroid lies 3 (2r - d)^2 / (4 (3r - d)) below the ball's centre.
        const double centroid = -2.0 - 3 * (2 * r - d) * (2 * r - d) / (4 * (3 * r - d));
        const double volumeError = std::abs(result.submergedVolume - cap) / ball;
        const double heightError = std::abs(result.centerOfBuoyancy.y() - centroid) / r;
        EXPECT_LT(volumeError, 1e-3);
        EXPECT_LT(heightError, 1e-3);
        worstVolume = std::max(worstVolume, volumeError);
        worstHeight = std::max(worstHeight, heightError);
        // The lathe is exactly symmetric about its axis.
        EXPECT_LT(std::hypot(result.centerOfBuoyancy.x() - 3, result.centerOfBuoyancy.z() - 7),
                  1e-12);
        EXPECT_NEAR(result.force.y(), rhoG() * result.submergedVolume, 1e-12 * result.force.y());
        expectPressureMatchesArchimedes(result, r);
    }
    std::printf(
        "  uv sphere 256x128 vs analytic caps: volume %.2e of the ball, C_B height %.2e "
        "of r\n",
        worstVolume, worstHeight);
}

TEST(BuoyancyExact, WaterAboveTheTopGivesTheExactSolid) {
    const TriangleMesh sphere = makeUvSphere(0.5, 64, 32);
    const MassProperties solid = exactSolidMassProperties(sphere, 1.0);
    // Torque about a point off the centroid, so the lever arm is not zero.
    const Vector3d centerOfMass(0.1, -0.2, 0.05);
    const Pose pose = Pose::fromEulerDegrees({4, 1, -6}, {20, 35, -10});
    const BuoyancyResult result = evaluate(sphere, pose, centerOfMass, 2.0);
    EXPECT_NEAR(result.submergedVolume, solid.volume, 1e-12 * solid.volume);
    EXPECT_LT((result.centerOfBuoyancy - pose.apply(solid.centerOfMass)).norm(), 1e-12);
    double surface = 0;  // m^2
    for (const Triangle& t : sphere.triangles) surface += triangleAreaVector(sphere, t).norm();
    EXPECT_NEAR(result.wettedArea, surface, 1e-12 * surface);
    EXPECT_GT(result.torque.norm(), 100.0);
    expectPressureMatchesArchimedes(result, 0.5);
}

TEST(BuoyancyExact, PartBelowPlusPartAboveIsTheWhole) {
    const TriangleMesh sphere = makeUvSphere(0.5, 64, 32);
    const TriangleMesh mirrored = mirroredInY(sphere);
    const MassProperties solid = exactSolidMassProperties(sphere, 1.0);
    const Pose identity;
    for (double h : {-0.45, -0.2, -1e-3, 0.0, 0.13, 0.31, 0.499}) {
        SCOPED_TRACE(h);
        const BuoyancyResult below = evaluate(sphere, identity, Vector3d::Zero(), h);
        const BuoyancyResult above = evaluate(mirrored, identity, Vector3d::Zero(), -h);
        EXPECT_NEAR(below.submergedVolume + above.submergedVolume, solid.volume,
                    1e-12 * solid.volume);
        Vector3d aboveCentroid = above.centerOfBuoyancy;
        aboveCentroid.y() = -aboveCentroid.y();
        const Vector3d moment =
            below.submergedVolume * below.centerOfBuoyancy + above.submergedVolume * aboveCentroid;
        EXPECT_LT((moment - solid.volume * solid.centerOfMass).norm(), 1e-12 * solid.volume);
        // An off-centre lever arm: still the same physics.
        expectPressureMatchesArchimedes(evaluate(sphere, identity, {0.2, 0.1, -0.3}, h), 0.8);
    }
}

// ---------------------------------------------------------------------------------------------
// Box: prisms, exact to rounding

TEST(BuoyancyExact, AxisAlignedBoxIsWidthTimesDepthTimesLength) {
    const TriangleMesh box = makeBox({1, 0.5, 0.25});
    const Vector3d centerOfMass(0.05, 0.1, -0.02);
    for (double h : {-0.2, -0.1, 0.0, 0.07, 0.2}) {
        SCOPED_TRACE(h);
        const Pose pose = Pose::fromEulerDegrees({10, -3, 5}, Vector3d::Zero());
        const BuoyancyResult result = evaluate(box, pose, centerOfMass, h - 3);
        const double depth = h + 0.25;  // m
        const double volume = 1.0 * depth * 0.25;
        EXPECT_NEAR(result.submergedVolume, volume, 1e-12 * volume);
        EXPECT_LT((result.centerOfBuoyancy - Vector3d(10, -3 + 0.5 * (h - 0.25), 5)).norm(), 1e-12);
        const double wetted = 1.0 * 0.25 + 2 * (1.0 + 0.25) * depth;  // bottom and sides, m^2
        EXPECT_NEAR(result.wettedArea, wetted, 1e-12 * wetted);
        expectPressureMatchesArchimedes(result, 1.0);
    }
}

TEST(BuoyancyExact, BoxTurnedFortyFiveDegreesIsAnAnalyticPrism) {
    // The 1 x 0.5 cross-section turned 45 degrees about z stands on a corner: the width of the
    // section at height s above that corner grows as 2 s up to s = a = 0.5/sqrt2 (the short
    // side ends), stays 2 a up to s = b = 1/sqrt2 (the long side ends), then shrinks.
    const double a = 0.5 / std::sqrt(2.0);
    const double b = 1.0 / std::sqrt(2.0);
    const double section = 0.5;  // m^2
    const auto areaBelow = [&](double s) {
        if (s <= a) return s * s;
        if (s <= b) return a * a + 2 * a * (s - a);
        return section - (a + b - s) * (a + b - s);
    };
    const TriangleMesh box = makeBox({1, 0.5, 0.25});
    const Pose pose = Pose::fromEulerDegrees({0, 0.5, 0}, {0, 0, 45});
    const double bottom = 0.5 - 0.5 * (a + b);  // world height of the lowest corner, m
    for (double s : {0.05, 0.2, a, 0.5, 0.7, b, 0.9, 1.0}) {
        SCOPED_TRACE(s);
        const BuoyancyResult result = evaluate(box, pose, Vector3d::Zero(), bottom + s);
        const double volume = areaBelow(s) * 0.25;
        EXPECT_NEAR(result.submergedVolume, volume, 1e-12 * volume);
        expectPressureMatchesArchimedes(result, 1.0);
    }
}

// ---------------------------------------------------------------------------------------------
// Edge cases

TEST(BuoyancyExact, PlaneThroughVerticesIsFiniteAndExact) {
    // Regular octahedron, water through its four equator vertices: the lower pyramid, volume
    // 2/3 and centroid a quarter of the way up from its base.
    const BuoyancyResult half = evaluate(octahedron({1, 0, 0}), Pose{}, Vector3d::Zero(), 0.0);
    EXPECT_NEAR(half.submergedVolume, 2.0 / 3.0, 1e-15);
    EXPECT_LT((half.centerOfBuoyancy - Vector3d(0, -0.25, 0)).norm(), 1e-15);
    expectPressureMatchesArchimedes(half, 1.0);

    // +x raised to (1, 0.5, 0): the plane now passes through three vertices and crosses the
    // edge to the bottom pole at (2/3, 0, 0), so some triangles have one vertex above, one on
    // and one below it. Part below: the pyramid from (0, -1, 0) over the kite (-1, 0, 0),
    // (0, 0, 1), (2/3, 0, 0), (0, 0, -1) of area 5/3 and centroid (-1/9, 0, 0).
    const BuoyancyResult kite = evaluate(octahedron({1, 0.5, 0}), Pose{}, Vector3d::Zero(), 0.0);
    EXPECT_NEAR(kite.submergedVolume, 5.0 / 9.0, 1e-14);
    EXPECT_LT((kite.centerOfBuoyancy - Vector3d(-1.0 / 12.0, -0.25, 0)).norm(), 1e-14);
    expectPressureMatchesArchimedes(kite, 1.0);

    // Box faces lying in the plane: the bottom one alone holds no water, the top one closes the
    // full box.
    const TriangleMesh box = makeBox({1, 0.5, 0.25});
    expectDry(evaluate(box, Pose{}, Vector3d::Zero(), -0.25), Vector3d::Zero());
    const BuoyancyResult full = evaluate(box, Pose{}, Vector3d::Zero(), 0.25);
    EXPECT_NEAR(full.submergedVolume, 0.125, 1e-15);
    EXPECT_LT(full.centerOfBuoyancy.norm(), 1e-15);
    // Plane through the middle, as the brief's box-centred-at-0 case.
    const BuoyancyResult middle = evaluate(box, Pose{}, Vector3d::Zero(), 0.0);
    EXPECT_NEAR(middle.submergedVolume, 0.0625, 1e-15);
    EXPECT_LT((middle.centerOfBuoyancy - Vector3d(0, -0.125, 0)).norm(), 1e-15);
}

TEST(BuoyancyExact, OutOfTheWaterIsZeroWithTheCentreOfBuoyancyAtTheCentreOfMass) {
    const TriangleMesh box = makeBox({1, 0.5, 0.25});
    const Pose pose = Pose::fromEulerDegrees({2, 5, -1}, {10, 20, 30});
    const Vector3d centerOfMass(0.1, 0.02, -0.03);
    expectDry(evaluate(box, pose, centerOfMass, 3.0), pose.apply(centerOfMass));
}

// ---------------------------------------------------------------------------------------------
// Far from the origin

TEST(BuoyancyExact, FarFromTheOriginKeepsItsDigits) {
    const TriangleMesh sphere = makeUvSphere(0.5, 64, 32);
    const Vector3d centerOfMass(0.1, -0.05, 0.02);
    const Vector3d degrees(15, -40, 25);
    const BuoyancyResult near =
        evaluate(sphere, Pose::fromEulerDegrees({0, 0, 0}, degrees), centerOfMass, 0.17);
    for (const Vector3d& far : {Vector3d(1e5, 0, -1e5), Vector3d(1e5, 1e5, -1e5)}) {
        SCOPED_TRACE(far.transpose());
        const BuoyancyResult result =
            evaluate(sphere, Pose::fromEulerDegrees(far, degrees), centerOfMass, 0.17 + far.y());
        EXPECT_NEAR(result.submergedVolume, near.submergedVolume, 1e-9 * near.submergedVolume);
        EXPECT_LT((result.centerOfBuoyancy - far - near.centerOfBuoyancy).norm(), 1e-9);
        EXPECT_LT((result.torque - near.torque).norm(), 1e-9 * near.force.norm());
        expectPressureMatchesArchimedes(result, 0.5);
    }
}

// ---------------------------------------------------------------------------------------------
// Shared public meshes: README values, exact rational arithmetic on the file's decimals

struct HalfSubmerged {
    const char* file;
    double level;               ///< h = (ymin + ymax) / 2
    double volume;              ///< V(y <= h)
    Vector3d centerOfBuoyancy;  ///< centroid of that part
};

const HalfSubmerged kReadme[] = {
    {"spot.obj", 0.108431, 0.46435262988465942, {-7.23091e-08, -0.225612705226, 0.383032175339}},
    {"blub_triangulated.obj",
     0.204129,
     0.85885116825822416,
     {3.81363e-07, -0.104133125446, 0.00617192763813}},
    {"boat.obj",
     1.865340891531311,
     8.7716909555334777,
     {-3.25601229497, 1.47417032154, -1.11037150555}},
    {"cube.obj", 0.0, 4.0, {0, -0.5, 0}},
    {"sphere.obj", 0.0, 2.0763424267454926, {0, -0.37393608131, 0}},
    {"torus.obj", 0.0, 0.60939224759569532, {0, -0.105496478564, 0}},
    {"bunny.obj",
     -0.0009195,
     0.58134172605348466,
     {0.0293704429997, -0.357395570104, 0.125275202802}},
};

TEST(BuoyancyExact, SharedMeshesHalfSubmergedMatchTheReadme) {
    int checked = 0;
    for (const HalfSubmerged& expected : kReadme) {
        const std::optional<TriangleMesh> mesh = test::loadSharedMesh(expected.file);
        if (!mesh) continue;
        SCOPED_TRACE(expected.file);
        const double diagonal = computeBounds(*mesh).diagonal();
        const Vector3d centerOfMass = exactSolidMassProperties(*mesh, 1.0).centerOfMass;
        const BuoyancyResult result = evaluate(*mesh, Pose{}, centerOfMass, expected.level);
        // assimp reads float32 coordinates: the README bounds that by 3.3e-8 of the volume.
        const double volumeError =
            std::abs(result.submergedVolume - expected.volume) / expected.volume;
        const double centerError =
            (result.centerOfBuoyancy - expected.centerOfBuoyancy).norm() / diagonal;
        EXPECT_LT(volumeError, 1e-6);
        EXPECT_LT(centerError, 1e-6);
        expectPressureMatchesArchimedes(result, diagonal);
        std::printf("  %-22s V(y<=h) %.2e relative, C_B %.2e of the diagonal\n", expected.file,
                    volumeError, centerError);
        ++checked;
    }
    if (checked == 0) GTEST_SKIP() << PLIMSOLL_SHARED_DIR "/meshes not present";
}

TEST(BuoyancyExact, SharedBoatFarFromTheOriginKeepsItsDigits) {
    const std::optional<TriangleMesh> boat = test::loadSharedMesh("boat.obj");
    if (!boat) GTEST_SKIP() << PLIMSOLL_SHARED_DIR "/meshes not present";
    const Vector3d centerOfMass = exactSolidMassProperties(*boat, 1.0).centerOfMass;
    const double level = 1.865340891531311;
    const BuoyancyResult near = evaluate(*boat, Pose{}, centerOfMass, level);
    const Vector3d far(1e5, 0, -1e5);
    const BuoyancyResult result =
        evaluate(*boat, Pose::fromEulerDegrees(far, Vector3d::Zero()), centerOfMass, level);
    EXPECT_NEAR(result.submergedVolume, near.submergedVolume, 1e-9 * near.submergedVolume);
    EXPECT_LT((result.centerOfBuoyancy - far - near.centerOfBuoyancy).norm(), 1e-9);
}

}  // namespace
}  // namespace test_buoyancy_exact
}  // namespace plimsoll
