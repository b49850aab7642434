// The body's mass properties as the glTF physics extensions game engines read today
// (docs/bundle.md, "glTF physics"): KHR_physics_rigid_bodies (Khronos draft) and
// OMI_physics_body (Godot's importer). Both describe inertia by its principal moments and the
// rotation from the principal axes into the node's space, so the tensor is diagonalised here.
#pragma once

#include "plimsoll/physics/massprops.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

namespace plimsoll::detail {

/// An inertia tensor in principal form: tensor = R diag(moments) R^T, R = orientation's
/// matrix, a proper rotation (det +1) from the principal axes into object axes. Moments are
/// ascending; the quaternion has w >= 0, so one tensor always gives the same numbers.
struct PrincipalInertia {
    Eigen::Vector3d moments = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

PrincipalInertia principalInertia(const Eigen::Matrix3d& inertia);

/// glTF's quaternion order: [x, y, z, w].
nlohmann::json gltfQuaternion(const Eigen::Quaterniond& q);

/// The node's `extensions` entries of a dynamic rigid body with mass properties `p`:
/// {"KHR_physics_rigid_bodies": {"motion": {...}}, "OMI_physics_body": {"motion": {...}}}.
nlohmann::json physicsNodeExtensions(const MassProperties& p);

}  // namespace plimsoll::detail
