// The exact mesh integrals against analytic solids and Mirtich's published tetrahedron.
#include "plimsoll/physics/massprops.h"
#include "plimsoll/samples/primitives.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace plimsoll {
namespace test_massprops_exact {
namespace {

TriangleMesh tetrahedron(const std::array<Eigen::Vector3d, 4>& v) {
    TriangleMesh mesh;
    mesh.source = "tetrahedron";
    mesh.positions.assign(v.begin(), v.end());
    mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return mesh;
}

// Mirtich's test tetrahedron: volume 10, centroid (1.25, 1, 0.75).
TEST(ExactMassProperties, MirtichTetrahedron) {
    const std::array<Eigen::Vector3d, 4> v = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(5, 0, 0),
                                              Eigen::Vector3d(0, 4, 0), Eigen::Vector3d(0, 0, 3)};
    const MassProperties p = exactSolidMassProperties(tetrahedron(v), 2.0);
    EXPECT_NEAR(p.volume, 10.0, 1e-12);
    EXPECT_NEAR(p.mass, 20.0, 1e-12);
    EXPECT_NEAR((p.centerOfMass - Eigen::Vector3d(1.25, 1.0, 0.75)).norm(), 0.0, 1e-12);

    // Independent reference: a tetrahedron's second moment about the origin is
    // (V/20) (sum v v^T + s s^T), s the vertex sum; then parallel axis and I = tr(S) Id - S.
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (const auto& x : v) {
        second += x * x.transpose();
        s += x;
    }
    second = (10.0 / 20.0) * (second + s * s.transpose());
    const Eigen::Vector3d c = s / 4.0;
    const Eigen::Matrix3d central = second - 10.0 * c * c.transpose();
    const Eigen::Matrix3d expected =
        2.0 * (central.trace() * Eigen::Matrix3d::Identity() - central);
    EXPECT_LT((p.inertia - expected).norm(), 1e-10 * expected.norm());
}

TEST(ExactMassProperties, BoxMatchesAnalyticAndTransformsAsATensor) {
    const Eigen::Vector3d size(1.0, 0.5, 0.25);
    TriangleMesh box = makeBox(size);
    const double density = 700.0;
    const double m = density * size.prod();
    const MassProperties p = exactSolidMassProperties(box, density);
    EXPECT_NEAR(p.volume, size.prod(), 1e-14);
    EXPECT_NEAR(p.mass, m, 1e-10);
    EXPECT_LT(p.centerOfMass.norm(), 1e-14);
    const Eigen::Vector3d sq = size.cwiseAbs2();
    const Eigen::Matrix3d expected =
        Eigen::Vector3d(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y()).asDiagonal() * (m / 12);
    EXPECT_LT((p.inertia - expected).norm(), 1e-12 * expected.norm());

    // Rotated and moved far away: the centre follows, the inertia becomes R I R^T.
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(-1.1, Eigen::Vector3d(1, 2, 3).normalized()))
                                  .toRotationMatrix();
    const Eigen::Vector3d t(1e5, -2e4, 3e5);
    for (auto& x : box.positions) x = R * x + t;
    const MassProperties moved = exactSolidMassProperties(box, density);
    EXPECT_LT((moved.centerOfMass - t).norm(), 1e-9);
    EXPECT_LT((moved.inertia - R * expected * R.transpose()).norm(), 1e-8 * expected.norm());
}

TEST(ExactMassProperties, CylinderIsExactlyItsPrism) {
    const double r = 0.3, h = 1.0;
    const int n = 64;
    const MassProperties p = exactSolidMassProperties(makeCylinder(r, h, n), 1.0);
    const double prism = 0.5 * n * r * r * std::sin(2 * std::numbers::pi / n) * h;
    EXPECT_NEAR(p.volume, prism, 1e-13);
    EXPECT_LT(p.centerOfMass.norm(), 1e-13);
    // Against the round cylinder, within the polygon's deficit (about (2 pi/n)^2 / 6).
    const double m = p.mass;
    const double radial = m * (3 * r * r + h * h) / 12, axial = m * r * r / 2;
    EXPECT_NEAR(p.inertia(1, 1), axial, 2e-3 * axial);
    EXPECT_NEAR(p.inertia(0, 0), radial, 2e-3 * radial);
    EXPECT_NEAR(p.inertia(2, 2), radial, 2e-3 * radial);
    EXPECT_LT(std::abs(p.inertia(0, 1)) + std::abs(p.inertia(1, 2)) + std::abs(p.inertia(0, 2)),
              1e-12 * axial);
}

TEST(ExactMassProperties, FineSphereConvergesToTheBall) {
    const double r = 0.5;
    const double ball = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    double previous = 1.0;
    for (int segments : {32, 64, 256}) {
        const MassProperties p =
            exactSolidMassProperties(makeUvSphere(r, segments, segments / 2), 1.0);
        // An inscribed polyhedron: below the ball by its tessellation error, O(1/n^2).
        const double error = (ball - p.volume) / ball;
        EXPECT_GT(error, 0.0);
        EXPECT_LT(error, 0.26 * previous);  // halving h quarters the error
        EXPECT_LT(error, 20.0 / (segments * segments));
        previous = error;
        EXPECT_LT(p.centerOfMass.norm(), 1e-12);
        const double expectedI = 0.4 * p.mass * r * r;
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(p.inertia(k, k), expectedI, 30.0 / (segments * segments) * expectedI);
    }
    EXPECT_LT(previous, 3e-4);  // 256 x 128: within 3e-4 of 4/3 pi r^3
}

TEST(ExactMassProperties, SphericalShellHasTwoThirdsMrSquared) {
    const double r = 0.5, sigma = 3.0;
    const MassProperties p = exactShellMassProperties(makeUvSphere(r, 256, 128), sigma);
    const double area = 4 * std::numbers::pi * r * r;
    EXPECT_NEAR(p.mass, sigma * area, 1e-3 * sigma * area);
    EXPECT_LT(p.centerOfMass.norm(), 1e-12);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(p.inertia(k, k), 2.0 / 3.0 * p.mass * r * r, 1e-3 * p.mass * r * r);
}

TEST(ExactMassProperties, SumUsesTheParallelAxisTheorem) {
    // Two unit cubes side by side are a 2 x 1 x 1 box.
    TriangleMesh a = makeBox(Eigen::Vector3d::Ones()), b = a;
    for (auto& x : a.positions) x.x() -= 0.5;
    for (auto& x : b.positions) x.x() += 0.5;
    const MassProperties sum = exactSolidMassProperties(a, 1.0) + exactSolidMassProperties(b, 1.0);
    const MassProperties whole = exactSolidMassProperties(makeBox(Eigen::Vector3d(2, 1, 1)), 1.0);
    EXPECT_NEAR(sum.mass, whole.mass, 1e-14);
    EXPECT_LT((sum.centerOfMass - whole.centerOfMass).norm(), 1e-14);
    EXPECT_LT((sum.inertia - whole.inertia).norm(), 1e-13);
}

}  // namespace
}  // namespace test_massprops_exact
}  // namespace plimsoll
