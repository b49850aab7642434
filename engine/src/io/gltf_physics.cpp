// glTF physics extensions (gltf_physics.h). Property names and meanings follow the drafts:
// KHR_physics_rigid_bodies' node.KHR_physics_rigid_bodies.motion.schema.json and
// OMI_physics_body's node.OMI_physics_body.motion.schema.json (versions cited in
// docs/bundle.md).
#include "io/gltf_physics.h"

#include <Eigen/Eigenvalues>

namespace plimsoll::detail {

using nlohmann::json;

PrincipalInertia principalInertia(const Eigen::Matrix3d& inertia) {
    // The tensor is symmetric by construction; symmetrise anyway so round-off in the
    // off-diagonal pairs cannot make the solver see two different matrices.
    const Eigen::Matrix3d symmetric = 0.5 * (inertia + inertia.transpose());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(symmetric);
    Eigen::Matrix3d axes = solver.eigenvectors();  // columns: principal axes, ascending moments
    // Eigenvectors come with arbitrary signs; a reflection (det -1) is no rotation, and
    // flipping one axis keeps R diag R^T unchanged.
    if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
    PrincipalInertia result;
    // Round-off can make a zero moment (a point mass, a rod) slightly negative; both drafts
    // require moments >= 0.
    result.moments = solver.eigenvalues().cwiseMax(0.0);
    result.orientation = Eigen::Quaterniond(axes).normalized();
    if (result.orientation.w() < 0) result.orientation.coeffs() = -result.orientation.coeffs();
    return result;
}

json gltfQuaternion(const Eigen::Quaterniond& q) {
    return json::array({q.x(), q.y(), q.z(), q.w()});
}

json physicsNodeExtensions(const MassProperties& p) {
    const PrincipalInertia principal = principalInertia(p.inertia);
    const json centerOfMass =
        json::array({p.centerOfMass.x(), p.centerOfMass.y(), p.centerOfMass.z()});
    const json moments =
        json::array({principal.moments.x(), principal.moments.y(), principal.moments.z()});
    const json orientation = gltfQuaternion(principal.orientation);
    // KHR: a node with `motion` is dynamic unless isKinematic. OMI: `type` is required.
    return json{{"KHR_physics_rigid_bodies",
                 {{"motion",
                   {{"mass", p.mass},
                    {"centerOfMass", centerOfMass},
                    {"inertiaDiagonal", moments},
                    {"inertiaOrientation", orientation}}}}},
                {"OMI_physics_body",
                 {{"motion",
                   {{"type", "dynamic"},
                    {"mass", p.mass},
                    {"centerOfMass", centerOfMass},
                    {"inertiaDiagonal", moments},
                    {"inertiaOrientation", orientation}}}}}};
}

}  // namespace plimsoll::detail
