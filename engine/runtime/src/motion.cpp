// The load the water puts on a body each step, and a semi-implicit Euler step for a body on
// its own (docs/bundle.md "Runtime library"): what a physics-engine adapter applies and what
// it is tested against.
#include "plimsoll_runtime/runtime.hpp"

#include "vec.hpp"

#include <algorithm>

namespace plimsoll_runtime {

namespace {

/// World inertia R I R^T times v.
Vec3 worldInertiaTimes(const double R[3][3], const double I[3][3], const Vec3& v) {
    const Vec3 b = mulT(R, v);
    return mul(R, Vec3{I[0][0] * b.x + I[0][1] * b.y + I[0][2] * b.z,
                       I[1][0] * b.x + I[1][1] * b.y + I[1][2] * b.z,
                       I[2][0] * b.x + I[2][1] * b.y + I[2][2] * b.z});
}

/// (R I R^T)^-1 v for a symmetric positive definite I (by cofactors; zero when singular).
Vec3 worldInertiaSolve(const double R[3][3], const double I[3][3], const Vec3& v) {
    const double c00 = I[1][1] * I[2][2] - I[1][2] * I[2][1];
    const double c01 = I[1][2] * I[2][0] - I[1][0] * I[2][2];
    const double c02 = I[1][0] * I[2][1] - I[1][1] * I[2][0];
    const double det = I[0][0] * c00 + I[0][1] * c01 + I[0][2] * c02;
    if (!(std::abs(det) > 0)) return {};
    const double inv[3][3] = {
        {c00 / det, (I[0][2] * I[2][1] - I[0][1] * I[2][2]) / det, (I[0][1] * I[1][2] - I[0][2] * I[1][1]) / det},
        {c01 / det, (I[0][0] * I[2][2] - I[0][2] * I[2][0]) / det, (I[0][2] * I[1][0] - I[0][0] * I[1][2]) / det},
        {c02 / det, (I[0][1] * I[2][0] - I[0][0] * I[2][1]) / det, (I[0][0] * I[1][1] - I[0][1] * I[1][0]) / det}};
    return worldInertiaTimes(R, inv, v);
}

/// At most what stops `momentum` within dt (dissipation must not reverse the motion).
Vec3 limited(const Vec3& loss, const Vec3& momentum, double dt) {
    const double impulse = norm(loss) * dt, cap = norm(momentum);
    return impulse > cap && impulse > 0 ? (cap / impulse) * loss : loss;
}

}  // namespace

WaterLoad waterLoad(const Bundle& bundle, const Pose& pose, const Velocity& velocity,
                    const Water& water, const Fluid& fluid, double time, double dt) {
    WaterLoad load;
    load.forces = bundle.evaluate(pose, velocity, water, fluid, time);
    const Forces& f = load.forces;
    load.force = f.force;
    load.torque = f.torque;
    double R[3][3];
    rotationMatrix(pose.orientation, R);
    const MassProperties& body = bundle.mass();
    if (const WaterGraph* graph = bundle.graph()) {
        const MassProperties inside = graph->waterMass(pose.orientation);
        if (inside.mass > 0) {
            const Vec3 weight{0, -inside.mass * fluid.gravity, 0};
            load.force += weight;
            load.torque += cross(mul(R, inside.centerOfMass - body.centerOfMass), weight);
            load.waterMass = inside.mass;
        }
    }
    const double wet = body.volume > 0 ? std::clamp(f.submergedVolume / body.volume, 0.0, 1.0) : 0.0;
    const Vec3 P = body.mass * velocity.linear;
    const Vec3 L = worldInertiaTimes(R, body.inertia, velocity.angular);
    load.force += limited(f.dragForce - (wet * bundle.linearDamping()) * P, P, dt);
    load.torque += limited(f.dragTorque - (wet * bundle.angularDamping()) * L, L, dt);
    return load;
}

void stepBody(Bundle& bundle, BodyState& state, const Water& water, const Fluid& fluid,
              double time, double dt) {
    if (WaterGraph* graph = bundle.graph()) graph->step(state.pose, water, time, dt);
    const WaterLoad load = waterLoad(bundle, state.pose, state.velocity, water, fluid, time, dt);
    const MassProperties& body = bundle.mass();
    double R[3][3];
    rotationMatrix(state.pose.orientation, R);
    const Vec3 center = mul(R, body.centerOfMass) + state.pose.position;
    // Momenta first ...
    const Vec3 P = body.mass * state.velocity.linear + dt * (load.force + Vec3{0, -body.mass * fluid.gravity, 0});
    const Vec3 L = worldInertiaTimes(R, body.inertia, state.velocity.angular) + dt * load.torque;
    const Vec3 v = (1.0 / body.mass) * P;
    const Vec3 w = worldInertiaSolve(R, body.inertia, L);
    // ... then position and orientation with the new velocities.
    Quat& q = state.pose.orientation;
    const Quat dq{-w.x * q.x - w.y * q.y - w.z * q.z, w.x * q.w + w.y * q.z - w.z * q.y,
                  w.y * q.w + w.z * q.x - w.x * q.z, w.z * q.w + w.x * q.y - w.y * q.x};
    q = {q.w + 0.5 * dt * dq.w, q.x + 0.5 * dt * dq.x, q.y + 0.5 * dt * dq.y, q.z + 0.5 * dt * dq.z};
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    q = {q.w / n, q.x / n, q.y / n, q.z / n};
    rotationMatrix(q, R);
    state.pose.position = center + dt * v - mul(R, body.centerOfMass);
    state.velocity.linear = v;
    // The angular velocity that carries L at the new orientation: L is what is conserved.
    state.velocity.angular = worldInertiaSolve(R, body.inertia, L);
}

}  // namespace plimsoll_runtime
