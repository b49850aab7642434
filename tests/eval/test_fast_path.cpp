// The fast CPU path (plimsoll_eval/fast.hpp through the fast backend) against the C++
// reference: every quantity within 1e-5 of its natural scale on flat water over random poses
// (at rest, moving, spinning, with and without skin friction), within the stated error on the
// sample projects' waves; the tile classes do what they claim (dry costs nothing, submerged
// tiles take the closed form and conserve the volume); the depth integrals of a wave stencil
// equal the sums over its entries.
#include "plimsoll/samples/primitives.h"

#include "eval/fast_support.h"

#include <gtest/gtest.h>

namespace plimsoll {
namespace test_fast_path {
namespace {

using namespace fast_test;

/// The largest error of each quantity over its natural scale: volume V, forces rho g V,
/// torques rho g V R, drag rho u^2 S (u the fastest entry's speed), its torque times R.
struct Errors {
    double volume = 0, force = 0, torque = 0, drag = 0, dragTorque = 0, wetted = 0, center = 0;
    void add(const BuoyancyResult& got, const BuoyancyResult& ref, const Body& body,
             const FluidSettings& fluid, double speed) {
        const double V = body.props.volume, R = body.radius, F = fluid.density * fluid.gravity * V;
        const double S = body.textures.surfaceArea();
        const double D = fluid.density * std::max(speed * speed, 1e-12) * S;
        volume = std::max(volume, std::abs(got.submergedVolume - ref.submergedVolume) / V);
        force = std::max({force, (got.force - ref.force).norm() / F,
                          (got.pressureForce - ref.pressureForce).norm() / F});
        torque = std::max({torque, (got.torque - ref.torque).norm() / (F * R),
                           (got.pressureTorque - ref.pressureTorque).norm() / (F * R)});
        drag = std::max(drag, (got.dragForce - ref.dragForce).norm() / D);
        dragTorque = std::max(dragTorque, (got.dragTorque - ref.dragTorque).norm() / (D * R));
        wetted = std::max(wetted, std::abs(got.wettedArea - ref.wettedArea) / S);
        // The centre of buoyancy weighed by the volume (it is undefined when nothing is wet).
        center = std::max(
            center,
            ((got.centerOfBuoyancy - ref.centerOfBuoyancy) * ref.submergedVolume).norm() / (V * R));
    }
    double worst() const {
        return std::max({volume, force, torque, drag, dragTorque, wetted, center});
    }
};

double speedOf(const BodyFrame& frame, const Body& body) {
    return frame.motion.linear.norm() + frame.motion.angular.norm() * body.radius;
}

TEST(FastPath, MatchesTheReferenceOnFlatWaterOverRandomPoses) {
    std::vector<Body> bodies;
    bodies.push_back(makeBody(makeUvSphere(0.5, 48, 24), 64));
    bodies.push_back(makeBody(makeBuoy(), 100));
    bodies.push_back(makeBody(makeBox({1.0, 0.4, 0.6}), 48));
    std::mt19937 random(20261201);
    ev::FastScratch scratch;
    for (const double friction : {0.0, 0.004}) {
        FluidSettings fluid;
        fluid.frictionCoefficient = friction;
        for (const Body& body : bodies) {
            Errors errors;
            int wet = 0;
            for (int trial = 0; trial < 150; ++trial) {
                const BodyFrame frame = randomFrame(random, body, trial % 3);
                const WaterModel water = WaterModel::flat(0.3 * std::sin(trial));
                const BuoyancyResult ref =
                    evaluateBuoyancyReference(body.textures, frame, water, fluid);
                const BuoyancyResult got =
                    evaluateBuoyancyFast(body.fast, frame, water, fluid, scratch);
                errors.add(got, ref, body, fluid, speedOf(frame, body));
                // A count differs only where an entry sits within rounding of the surface.
                EXPECT_NEAR(double(got.submergedSamples), double(ref.submergedSamples), 2.0);
                wet += ref.submergedVolume > 0 && ref.submergedVolume < body.props.volume;
            }
            EXPECT_GT(wet, 50);  // the poses cross the waterline
            EXPECT_LE(errors.worst(), 1e-5)
                << "volume " << errors.volume << " force " << errors.force << " torque "
                << errors.torque << " drag " << errors.drag << " drag torque " << errors.dragTorque
                << " wetted " << errors.wetted << " centre " << errors.center;
        }
    }
}

// On waves the fast path takes the water from a 9 x 9 grid of heights over the body's
// footprint (a quadratic per tile) and the water's velocity at each tile's centre: measured
// here on the buoy project's two Gerstner waves against the reference's per-entry heights.
TEST(FastPath, OnTheSampleWavesStaysWithinTheStatedError) {
    std::vector<Body> bodies;
    bodies.push_back(makeBody(makeBuoy(), 128));
    bodies.push_back(makeBody(makeUvSphere(0.5, 48, 24), 64));
    const WaterModel water = buoyWaves();
    std::mt19937 random(7);
    ev::FastScratch scratch;
    const FluidSettings fluid;
    for (const Body& body : bodies) {
        Errors errors;
        for (int trial = 0; trial < 120; ++trial) {
            const BodyFrame frame = randomFrame(random, body, trial % 3);
            errors.add(evaluateBuoyancyFast(body.fast, frame, water, fluid, scratch),
                       evaluateBuoyancyReference(body.textures, frame, water, fluid), body, fluid,
                       speedOf(frame, body) + 1.0);
        }
        std::printf(
            "  waves, %zu entries: volume %.1e, force %.1e, torque %.1e, drag %.1e, "
            "drag torque %.1e of scale\n",
            body.textures.coveredCount(), errors.volume, errors.force, errors.torque, errors.drag,
            errors.dragTorque);
        EXPECT_LE(errors.force, 1e-3);
        EXPECT_LE(errors.volume, 1e-3);
        EXPECT_LE(errors.torque, 1e-3);
        // The water's velocity taken at each tile's centre: drag is the coarser quantity.
        EXPECT_LE(errors.drag, 1e-2);
        EXPECT_LE(errors.dragTorque, 1e-2);
    }
}

TEST(FastPath, DryTilesCostNothingAndSubmergedTilesTakeTheClosedForm) {
    const Body sphere = makeBody(makeUvSphere(0.5, 48, 24), 64);
    ev::FastScratch scratch;
    ev::FastStats stats;
    BodyFrame frame;
    frame.centerOfMass = sphere.props.centerOfMass;
    frame.pose = Pose::fromEulerDegrees({0, 0, 0}, {20, 30, 40});
    const FluidSettings fluid;
    // Clear of the water: nothing at all.
    BuoyancyResult r =
        evaluateBuoyancyFast(sphere.fast, frame, WaterModel::flat(-1.0), fluid, scratch, &stats);
    EXPECT_EQ(r.submergedVolume, 0.0);
    EXPECT_EQ(stats.perEntry + stats.closedForm, 0u);
    // Deep under, at rest: every tile in closed form, equal to the per-entry sums in double,
    // and the volume the body's (to the texture's discretisation).
    r = evaluateBuoyancyFast(sphere.fast, frame, WaterModel::flat(5.0), fluid, scratch, &stats);
    EXPECT_EQ(stats.perEntry, 0u);
    EXPECT_GT(stats.closedForm, 0u);
    const BuoyancyResult deep =
        evaluateBuoyancyReference(sphere.textures, frame, WaterModel::flat(5.0), fluid);
    EXPECT_NEAR(r.submergedVolume, deep.submergedVolume, 1e-6 * sphere.props.volume);
    EXPECT_LT((r.pressureForce - deep.pressureForce).norm(), 1e-6 * r.force.norm());
    EXPECT_LT((r.pressureTorque - deep.pressureTorque).norm(),
              1e-6 * r.force.norm() * sphere.radius);
    EXPECT_LT((r.centerOfBuoyancy - deep.centerOfBuoyancy).norm(), 1e-6 * sphere.radius);
    EXPECT_EQ(r.submergedSamples, sphere.textures.coveredCount());
    EXPECT_NEAR(r.submergedVolume, sphere.props.volume, 1e-3 * sphere.props.volume);
    // Deep under waves: the closed form takes the curved surface too; only tiles across which
    // the sign of A.u changes (u the water's orbital velocity, small down there) go per entry.
    WaterModel deepWaves = buoyWaves();
    deepWaves.level = 5.0;
    r = evaluateBuoyancyFast(sphere.fast, frame, deepWaves, fluid, scratch, &stats);
    EXPECT_GT(stats.closedForm, stats.perEntry);
    EXPECT_GT(stats.waterSamples, 0u);
    const BuoyancyResult underWaves =
        evaluateBuoyancyReference(sphere.textures, frame, deepWaves, fluid);
    EXPECT_LT((r.pressureForce - underWaves.pressureForce).norm(), 1e-4 * r.force.norm());
    // Moving and spinning deep under: the drag of tiles whose normals keep their sign against
    // the flow is summed from the moments, and equals the reference's per-entry sum.
    frame.motion.linear = {0.8, -0.3, 0.2};
    frame.motion.angular = {0.1, 0.2, -0.1};
    r = evaluateBuoyancyFast(sphere.fast, frame, WaterModel::flat(5.0), fluid, scratch, &stats);
    EXPECT_GT(stats.closedForm, stats.perEntry);
    const BuoyancyResult ref =
        evaluateBuoyancyReference(sphere.textures, frame, WaterModel::flat(5.0), fluid);
    EXPECT_LT((r.dragForce - ref.dragForce).norm(), 1e-5 * ref.dragForce.norm());
    EXPECT_LT((r.dragTorque - ref.dragTorque).norm(), 1e-5 * ref.dragForce.norm() * sphere.radius);
    // Half under at rest: only leaves (8 entries) near the waterline take per-entry work.
    r = evaluateBuoyancyFast(sphere.fast, {frame.pose, {}, frame.centerOfMass, 0.0},
                             WaterModel::flat(frame.pose.apply(sphere.props.centerOfMass).y()),
                             fluid, scratch, &stats);
    EXPECT_LT(stats.perEntry * 8, sphere.textures.coveredCount() / 4);
    EXPECT_GT(stats.dry, 0u);
    EXPECT_GT(stats.closedForm, 0u);
}

// The closed form of a wave stencil's bucket (depthIntegrals), from moments about c, equals the
// same integrals summed entry by entry: the depth d = alpha + beta.s + s^T H s / 2 about the
// stencil's point p (s = q - p), sum d b, sum d b q^T about c, and sum (d^2 - (s^T H s)^2 / 4) b;
// on curved water and, with orders 0 to 2 only, under a plane.
TEST(FastPath, DepthIntegralsEqualTheSumsOverEntries) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<ev::Vec3> q(40), b(40);
    ev::FastMoments moments;  // about c, as FastBody keeps them
    for (std::size_t i = 0; i < q.size(); ++i) {
        q[i] = {u(rng), u(rng), u(rng)};
        b[i] = {u(rng), u(rng), u(rng)};
        const double s[3] = {q[i].x, q[i].y, q[i].z}, a[3] = {b[i].x, b[i].y, b[i].z};
        for (int k = 0; k < 3; ++k) {
            moments.n0[k] += a[k];
            for (int j = 0; j < 3; ++j) {
                moments.n1[k][j] += a[k] * s[j];
                for (int l = j; l < 3; ++l) {
                    moments.n2[k][ev::kPair[j][l]] += a[k] * s[j] * s[l];
                    for (int n = l; n < 3; ++n)
                        moments.n3[k][ev::kTriple[j][l][n]] += a[k] * s[j] * s[l] * s[n];
                }
            }
        }
    }
    const ev::Vec3 p{0.3, -0.7, 0.45};
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, 2, -1).normalized()).toRotationMatrix();
    ev::Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = R(i, j);
    const double alpha = 0.37;
    const ev::Vec3 beta{0.21, -0.93, 0.08};
    for (const bool curved : {true, false}) {
        double H[3][3] = {};
        if (curved) ev::objectHessian(r, 0.4, -0.25, 0.9, H);
        ev::FastMoments given = moments;
        if (!curved)  // a flat bucket sums orders 0 to 2 only: the third must not be read
            for (auto& row : given.n3)
                for (double& v : row) v = std::nan("");
        const ev::FastDepthIntegrals got = ev::depthIntegrals(given, p, alpha, beta, H);
        ev::FastDepthIntegrals direct;
        for (std::size_t i = 0; i < q.size(); ++i) {
            const double s[3] = {q[i].x - p.x, q[i].y - p.y, q[i].z - p.z};
            double sHs = 0;
            for (int j = 0; j < 3; ++j)
                for (int l = 0; l < 3; ++l) sHs += s[j] * H[j][l] * s[l];
            const double d = alpha + beta.x * s[0] + beta.y * s[1] + beta.z * s[2] + 0.5 * sHs;
            const double a[3] = {b[i].x, b[i].y, b[i].z}, qc[3] = {q[i].x, q[i].y, q[i].z};
            for (int k = 0; k < 3; ++k) {
                direct.d0[k] += d * a[k];
                for (int j = 0; j < 3; ++j) direct.d1[k][j] += d * a[k] * qc[j];
                direct.e[k] += (d * d - 0.25 * sHs * sHs) * a[k];
            }
        }
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(got.d0[k], direct.d0[k], 1e-12) << "curved " << curved << ", u " << k;
            for (int j = 0; j < 3; ++j)
                EXPECT_NEAR(got.d1[k][j], direct.d1[k][j], 1e-12) << "u " << k << ", j " << j;
            EXPECT_NEAR(got.e[k], direct.e[k], 1e-12) << "curved " << curved << ", u " << k;
        }
        if (!curved) continue;
        // The object-axes Hessian R^T H3 R, H3's y row and column zero: symmetric, and the
        // world's vertical in object axes (R^T e_y) in its null space.
        const ev::Vec3 up{R(1, 0), R(1, 1), R(1, 2)};
        for (int i = 0; i < 3; ++i) {
            EXPECT_NEAR(H[i][0] * up.x + H[i][1] * up.y + H[i][2] * up.z, 0.0, 1e-12);
            for (int j = 0; j < 3; ++j) EXPECT_NEAR(H[i][j], H[j][i], 1e-12);
        }
    }
}

}  // namespace
}  // namespace test_fast_path
}  // namespace plimsoll
