// Rigid-body state and integrators: conservation on a tumbling box, free fall and a spring
// against their closed forms, constant torque, and the pose/state conversions.
#include "plimsoll/physics/rigid_body.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace plimsoll {
namespace test_rigid_body {
namespace {

constexpr std::array kAllIntegrators = {Integrator::ExplicitEuler, Integrator::SemiImplicitEuler,
                                        Integrator::RK4};

/// A 1 x 0.5 x 0.25 m box of 1 kg (x longest, y intermediate, z shortest), its centre of mass
/// off the object origin so that poseOf's translation differs from the position.
MassDistribution box() {
    const double m = 1.0, a = 1.0, b = 0.5, c = 0.25;
    MassDistribution mass;
    mass.mass = m;
    mass.inertia = Eigen::Vector3d(m * (b * b + c * c) / 12, m * (a * a + c * c) / 12,
                                   m * (a * a + b * b) / 12)
                       .asDiagonal();
    mass.centerOfMass = {0.1, -0.2, 0.3};
    return mass;
}

Pose tiltedPose() { return Pose::fromEulerDegrees({1.0, 2.0, 3.0}, {20.0, -35.0, 50.0}); }

Wrench noWrench(const RigidBodyState&, double) { return {}; }

/// The box spinning at 5 rad/s about its intermediate axis with a small perturbation: unstable
/// (Dzhanibekov effect), so within 10 s it flips over. (0.01, 5, 0.01) would not do: for this
/// box it lies on the stable manifold of the linearised motion, wx' = -3 wz, wz' = -3 wx.
RigidBodyState tumblingBox() {
    const Pose pose = tiltedPose();
    Motion motion;
    motion.linear = {0.5, -1.0, 2.0};
    motion.angular = pose.rotation * Eigen::Vector3d(0.02, 5.0, 0.01);
    return stateAt(pose, box(), motion);
}

TEST(RigidBody, IntegratorNamesRoundTrip) {
    for (Integrator integrator : kAllIntegrators) {
        EXPECT_EQ(integratorFromName(integratorName(integrator)), integrator);
    }
    EXPECT_STREQ(integratorName(Integrator::SemiImplicitEuler), "semi-implicit-euler");
    EXPECT_EQ(integratorFromName("RK4"), std::nullopt);
    EXPECT_EQ(integratorFromName("verlet"), std::nullopt);
    EXPECT_EQ(integratorFromName(""), std::nullopt);
}

TEST(RigidBody, PoseAndStateRoundTrip) {
    const MassDistribution mass = box();
    const Pose pose = tiltedPose();
    const Motion motion{{0.3, -0.4, 1.2}, {-2.0, 0.7, 1.5}};
    const RigidBodyState state = stateAt(pose, mass, motion);

    EXPECT_NEAR((state.position - pose.apply(mass.centerOfMass)).norm(), 0.0, 1e-15);
    const Pose back = poseOf(state, mass);
    EXPECT_NEAR((back.rotation - pose.rotation).norm(), 0.0, 1e-14);
    EXPECT_NEAR((back.translation - pose.translation).norm(), 0.0, 1e-14);
    EXPECT_NEAR((linearVelocity(state, mass) - motion.linear).norm(), 0.0, 1e-15);
    EXPECT_NEAR((angularVelocity(state, mass) - motion.angular).norm(), 0.0, 1e-13);

    const double expected = 0.5 * mass.mass * motion.linear.squaredNorm() +
                            0.5 * motion.angular.dot(worldInertia(state, mass) * motion.angular);
    EXPECT_NEAR(kineticEnergy(state, mass), expected, 1e-13);
}

TEST(RigidBody, WorldInertiaIsRotatedBodyInertia) {
    MassDistribution mass = box();
    mass.inertia(0, 1) = mass.inertia(1, 0) = -0.004;  // a product of inertia too
    const RigidBodyState state = stateAt(tiltedPose(), mass, {});
    const Eigen::Matrix3d r = tiltedPose().rotation;
    const Eigen::Matrix3d inertia = worldInertia(state, mass);

    EXPECT_NEAR((inertia - inertia.transpose()).norm(), 0.0, 1e-15);
    EXPECT_NEAR((inertia - r * mass.inertia * r.transpose()).norm(), 0.0, 1e-15);
    // Rotation does not change the principal moments.
    const Eigen::Vector3d world =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia).eigenvalues();
    const Eigen::Vector3d body =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(mass.inertia).eigenvalues();
    EXPECT_NEAR((world - body).norm(), 0.0, 1e-15);
}

// L is constant without torque in every integrator (world-frame momentum); the energy is the
// measure that tells them apart. Semi-implicit Euler must never gain energy; the others are
// measured and printed (explicit Euler gains, RK4 drifts slowly).
TEST(RigidBody, TorqueFreeTumblingBox) {
    constexpr int kSteps = 10000;
    constexpr double kDt = 1e-3;
    const MassDistribution mass = box();
    const RigidBodyState start = tumblingBox();
    const double startEnergy = kineticEnergy(start, mass);

    for (Integrator integrator : kAllIntegrators) {
        RigidBodyState state = start;
        double maxEnergy = startEnergy, minBodySpin = 5.0;
        for (int i = 0; i < kSteps; ++i) {
            state = step(state, mass, noWrench, i * kDt, kDt, integrator);
            maxEnergy = std::max(maxEnergy, kineticEnergy(state, mass));
            const Eigen::Vector3d bodySpin =
                state.orientation.conjugate() * angularVelocity(state, mass);
            minBodySpin = std::min(minBodySpin, bodySpin.y());
        }
        const double drift = kineticEnergy(state, mass) / startEnergy - 1.0;
        std::printf("[ measured ] %s: energy drift %+.3e after %d steps (max %+.3e)\n",
                    integratorName(integrator), drift, kSteps, maxEnergy / startEnergy - 1.0);

        EXPECT_LT(minBodySpin, -4.0) << integratorName(integrator) << ": the box never flipped";
        EXPECT_NEAR(state.angularMomentum.norm() / start.angularMomentum.norm(), 1.0, 1e-6)
            << integratorName(integrator);
        const Eigen::Vector3d expectedPosition =
            start.position + kSteps * kDt * linearVelocity(start, mass);
        EXPECT_NEAR((state.position - expectedPosition).norm(), 0.0, 1e-9);
        if (integrator == Integrator::SemiImplicitEuler) {
            EXPECT_LE(maxEnergy, startEnergy * (1.0 + 1e-6));
        }
    }
}

TEST(RigidBody, Rk4KeepsTheQuaternionUnit) {
    const MassDistribution mass = box();
    RigidBodyState state = tumblingBox();
    for (int i = 0; i < 10000; ++i) {
        state = step(state, mass, noWrench, i * 1e-3, 1e-3, Integrator::RK4);
    }
    EXPECT_LT(std::abs(state.orientation.norm() - 1.0), 1e-12);
}

// x(t) = x0 + v0 t + g t^2 / 2 (g the gravity vector). With v_k = v0 + g k dt, the Euler
// variants sum the velocities at the end (semi-implicit) or the start (explicit) of each step:
// x_n = x0 + v0 t + g t^2 / 2 +- g t dt / 2, an error of exactly |g| t dt / 2. RK4 integrates
// the quadratic exactly.
TEST(RigidBody, FreeFall) {
    constexpr int kSteps = 1000;
    constexpr double kDt = 1e-3;
    const double t = kSteps * kDt;
    const MassDistribution mass = box();
    const Eigen::Vector3d gravity(0.0, -9.81, 0.0);
    const WrenchFunction weight = [&](const RigidBodyState&, double) {
        return Wrench{mass.mass * gravity, Eigen::Vector3d::Zero()};
    };
    const RigidBodyState start = stateAt(tiltedPose(), mass, {.linear = {0.5, 3.0, -1.0}});
    const Eigen::Vector3d x0 = start.position, v0 = linearVelocity(start, mass);
    const Eigen::Vector3d exact = x0 + v0 * t + gravity * t * t / 2;
    const Eigen::Vector3d eulerError = gravity * t * kDt / 2;

    for (Integrator integrator : kAllIntegrators) {
        RigidBodyState state = start;
        for (int i = 0; i < kSteps; ++i) {
            state = step(state, mass, weight, i * kDt, kDt, integrator);
        }
        const Eigen::Vector3d error = state.position - exact;
        const Eigen::Vector3d expected = integrator == Integrator::SemiImplicitEuler ? eulerError
                                         : integrator == Integrator::ExplicitEuler
                                             ? Eigen::Vector3d(-eulerError)
                                             : Eigen::Vector3d::Zero();
        EXPECT_NEAR((error - expected).norm(), 0.0, 1e-9) << integratorName(integrator);
        EXPECT_NEAR((linearVelocity(state, mass) - (v0 + gravity * t)).norm(), 0.0, 1e-11);
        EXPECT_NEAR(state.orientation.angularDistance(start.orientation), 0.0, 1e-12);
    }
}

/// A point-like body (the spring acts on the centre of mass) on a spring F = -k x:
/// omega = sqrt(k / m) = 2 rad/s.
struct Spring {
    MassDistribution mass = box();
    double stiffness = 4.0;  ///< N/m, with the box's 1 kg
    double omega() const { return std::sqrt(stiffness / mass.mass); }
    double period() const { return 2 * std::numbers::pi / omega(); }
    WrenchFunction wrench() const {
        return [k = stiffness](const RigidBodyState& s, double) {
            return Wrench{-k * s.position, Eigen::Vector3d::Zero()};
        };
    }
    double energy(const RigidBodyState& s) const {
        return kineticEnergy(s, mass) + 0.5 * stiffness * s.position.squaredNorm();
    }
    RigidBodyState start() const {
        return stateAt(Pose{Eigen::Matrix3d::Identity(), {0.3, -0.2, 0.1}}, mass,
                       {.linear = {0.0, 0.5, 0.0}});
    }
};

TEST(RigidBody, SpringRk4OnePeriod) {
    const Spring spring;
    const int steps = 1000;
    const double dt = spring.period() / steps;
    const RigidBodyState start = spring.start();
    RigidBodyState state = start;
    for (int i = 0; i < steps; ++i) {
        state = step(state, spring.mass, spring.wrench(), i * dt, dt, Integrator::RK4);
    }
    EXPECT_LT((state.position - start.position).norm(), 1e-8);
    EXPECT_LT((state.linearMomentum - start.linearMomentum).norm(), 1e-8);
}

// Symplectic Euler keeps a modified energy exactly (Hairer, Lubich & Wanner, ch. IX): the true
// energy oscillates by about omega dt / 2 and never grows.
TEST(RigidBody, SpringSemiImplicitEnergyIsBounded) {
    const Spring spring;
    const int stepsPerPeriod = 1000, periods = 100;
    const double dt = spring.period() / stepsPerPeriod;
    RigidBodyState state = spring.start();
    const double startEnergy = spring.energy(state);
    double firstPeriodMax = 0, lastPeriodMax = 0, worst = 0;
    for (int i = 0; i < stepsPerPeriod * periods; ++i) {
        state =
            step(state, spring.mass, spring.wrench(), i * dt, dt, Integrator::SemiImplicitEuler);
        const double energy = spring.energy(state);
        worst = std::max(worst, std::abs(energy / startEnergy - 1.0));
        if (i < stepsPerPeriod) firstPeriodMax = std::max(firstPeriodMax, energy);
        if (i >= stepsPerPeriod * (periods - 1)) lastPeriodMax = std::max(lastPeriodMax, energy);
    }
    EXPECT_LT(worst, 0.01);
    EXPECT_GT(worst, 0.0);  // it does oscillate
    EXPECT_LE(lastPeriodMax, firstPeriodMax * (1.0 + 1e-6));
}

// The paper's explicit Euler multiplies the energy of a harmonic oscillator by exactly
// 1 + (omega dt)^2 each step: (omega x, v) -> a rotation scaled by sqrt(1 + (omega dt)^2).
TEST(RigidBody, SpringExplicitEulerEnergyGrows) {
    const Spring spring;
    const int steps = 100 * 1000;
    const double dt = spring.period() / 1000;
    RigidBodyState state = spring.start();
    const double startEnergy = spring.energy(state);
    for (int i = 0; i < steps; ++i) {
        state = step(state, spring.mass, spring.wrench(), i * dt, dt, Integrator::ExplicitEuler);
    }
    const double growth = std::pow(1.0 + std::pow(spring.omega() * dt, 2), steps);
    EXPECT_GT(growth, 50.0);
    EXPECT_NEAR(spring.energy(state) / startEnergy / growth, 1.0, 1e-9);
}

// Spinning about a principal axis with the torque along it: the axis stays put, L grows
// linearly and w = L / I about that axis, for every integrator.
TEST(RigidBody, ConstantTorqueAboutAPrincipalAxis) {
    constexpr int kSteps = 1000;
    constexpr double kDt = 1e-3;
    const MassDistribution mass = box();
    const double moment = mass.inertia(2, 2);
    const Pose pose = tiltedPose();
    const Eigen::Vector3d axis = pose.rotation.col(2);
    const Eigen::Vector3d torque = 0.3 * axis;
    const WrenchFunction twist = [&](const RigidBodyState&, double) {
        return Wrench{Eigen::Vector3d::Zero(), torque};
    };
    const RigidBodyState start = stateAt(pose, mass, {.angular = 2.0 * axis});

    for (Integrator integrator : kAllIntegrators) {
        RigidBodyState state = start;
        for (int i = 0; i < kSteps; ++i) {
            state = step(state, mass, twist, i * kDt, kDt, integrator);
        }
        const Eigen::Vector3d momentum = start.angularMomentum + torque * kSteps * kDt;
        EXPECT_NEAR((state.angularMomentum - momentum).norm(), 0.0, 1e-13)
            << integratorName(integrator);
        EXPECT_NEAR((angularVelocity(state, mass) - momentum / moment).norm(), 0.0, 1e-12)
            << integratorName(integrator);
        EXPECT_NEAR((poseOf(state, mass).rotation.col(2) - axis).norm(), 0.0, 1e-12);
    }
}

}  // namespace
}  // namespace test_rigid_body
}  // namespace plimsoll
