// Rigid placement and motion of a body in the world.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace plimsoll {

/// Maps an object-space point p to rotation * p + translation (world, m).
struct Pose {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();

    Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return rotation * p + translation; }

    /// R = Rz(rz) Ry(ry) Rx(rx): about x first, then y, then z, fixed axes (degrees).
    static Pose fromEulerDegrees(const Eigen::Vector3d& position, const Eigen::Vector3d& degrees);
};

/// Velocity of the body: linear velocity of its centre of mass and angular velocity, world axes.
struct Motion {
    Eigen::Vector3d linear = Eigen::Vector3d::Zero();   ///< m/s
    Eigen::Vector3d angular = Eigen::Vector3d::Zero();  ///< rad/s
};

}  // namespace plimsoll
