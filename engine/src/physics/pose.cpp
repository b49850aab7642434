#include "plimsoll/physics/pose.h"

#include <numbers>

namespace plimsoll {

Pose Pose::fromEulerDegrees(const Eigen::Vector3d& position, const Eigen::Vector3d& degrees) {
    const Eigen::Vector3d radians = degrees * (std::numbers::pi / 180.0);
    Pose pose;
    // Fixed axes, x first: the rightmost factor acts first on a column vector.
    pose.rotation = (Eigen::AngleAxisd(radians.z(), Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(radians.y(), Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(radians.x(), Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    pose.translation = position;
    return pose;
}

}  // namespace plimsoll
