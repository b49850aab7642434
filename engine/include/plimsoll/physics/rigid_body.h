// Rigid-body state and time integrators (docs/design.md, "Rigid body"). The state is (x, q, P, L):
// centre of mass, orientation, linear and angular momentum, all in world axes, so that
// without a wrench P and L stay exactly constant whatever the integrator. Velocities follow
// from the momenta: v = P / m, w = I_world^-1 L with I_world = R I_body R^T, which puts the
// gyroscopic terms in without writing Euler's equations (Baraff, "Physically Based Modeling:
// Rigid Body Simulation", SIGGRAPH 2001 course notes).
#pragma once

#include "plimsoll/physics/pose.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <functional>
#include <optional>
#include <string_view>

namespace plimsoll {

/// What the integrators need of a body's mass properties (same conventions as MassProperties).
struct MassDistribution {
    double mass = 0;  ///< kg, > 0
    /// Inertia tensor about the centre of mass, object (body) axes, kg m^2; symmetric positive
    /// definite.
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();  ///< object space, m
    /// Infinite-frequency added mass of the water around the body (cummins.h), object axes:
    /// the translational block (kg) joins the mass and the rotational block (kg m^2, about the
    /// centre of mass) the inertia wherever a velocity is taken from a momentum, so the
    /// integrators carry it implicitly; gravity still acts on `mass` alone. Zero without
    /// radiation (then everything is as for a bare rigid body).
    Eigen::Matrix3d addedMass = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d addedInertia = Eigen::Matrix3d::Zero();
};

struct RigidBodyState {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< centre of mass, world, m
    /// Object -> world rotation, unit quaternion.
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    Eigen::Vector3d linearMomentum = Eigen::Vector3d::Zero();  ///< world, kg m/s
    /// World axes, about the centre of mass, kg m^2/s.
    Eigen::Vector3d angularMomentum = Eigen::Vector3d::Zero();
};

/// Total force and torque on a body.
struct Wrench {
    Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< world, N
    Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< world, about the centre of mass, N m
};

enum class Integrator {
    /// Every derivative at the start of the step (the paper's integrator; gains energy).
    ExplicitEuler,
    /// Symplectic Euler: momenta first with the wrench at the start of the step, then position
    /// and orientation with the new velocities. The product's default.
    SemiImplicitEuler,
    /// Classical fourth-order Runge-Kutta on (x, q, P, L).
    RK4,
};

/// "explicit-euler", "semi-implicit-euler", "rk4".
const char* integratorName(Integrator integrator);
/// Inverse of integratorName; nullopt for any other name.
std::optional<Integrator> integratorFromName(std::string_view name);

/// The wrench on the body in a given state at a given time (s). The integrators call it once
/// per step (Euler) or four times (RK4, at t, t + dt/2 twice and t + dt).
using WrenchFunction = std::function<Wrench(const RigidBodyState&, double time)>;

/// R I_body R^T (kg m^2): the inertia tensor in world axes, about the centre of mass.
Eigen::Matrix3d worldInertia(const RigidBodyState& state, const MassDistribution& mass);
/// P / m (m/s): velocity of the centre of mass ((m + R A R^T)^-1 P with added mass A).
Eigen::Vector3d linearVelocity(const RigidBodyState& state, const MassDistribution& mass);
/// I_world^-1 L (rad/s, world axes), the inertia including the added inertia.
Eigen::Vector3d angularVelocity(const RigidBodyState& state, const MassDistribution& mass);
/// Object -> world placement: rotation R(q), translation x - R c (c the object-space centre of
/// mass), so that the pose maps c onto x.
Pose poseOf(const RigidBodyState& state, const MassDistribution& mass);
/// Inverse of poseOf plus the velocities: motion.linear is the velocity of the centre of mass,
/// motion.angular the angular velocity, world axes. pose.rotation must be a rotation.
RigidBodyState stateAt(const Pose& pose, const MassDistribution& mass, const Motion& motion);
/// P.v / 2 + L.w / 2 (J): the body's and, with added mass, the entrained water's.
double kineticEnergy(const RigidBodyState& state, const MassDistribution& mass);

/// One step of length dt (s) from `time` (s); the quaternion comes back renormalised.
RigidBodyState step(const RigidBodyState& state, const MassDistribution& mass,
                    const WrenchFunction& wrench, double time, double dt, Integrator integrator);

}  // namespace plimsoll
