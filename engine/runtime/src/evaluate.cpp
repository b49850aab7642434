// Buoyancy, pressure and drag over the bundle's sample list: a line-for-line port of the
// engine's evaluateBuoyancyReference (engine/src/buoyancy_reference.cpp) and finishBuoyancy,
// so the conformance test can hold the two to rounding (tests/test_runtime_conformance.cpp).
#include "plimsoll_runtime/runtime.hpp"

#include "vec.hpp"

#include <algorithm>
#include <cmath>

namespace plimsoll_runtime {

void rotationMatrix(const Quat& q, double R[3][3]) {
    // Eigen's QuaternionBase::toRotationMatrix, term for term.
    const double tx = 2 * q.x, ty = 2 * q.y, tz = 2 * q.z;
    const double twx = tx * q.w, twy = ty * q.w, twz = tz * q.w;
    const double txx = tx * q.x, txy = ty * q.x, txz = tz * q.x;
    const double tyy = ty * q.y, tyz = tz * q.y, tzz = tz * q.z;
    R[0][0] = 1 - (tyy + tzz);
    R[0][1] = txy - twz;
    R[0][2] = txz + twy;
    R[1][0] = txy + twz;
    R[1][1] = 1 - (txx + tzz);
    R[1][2] = tyz - twx;
    R[2][0] = txz - twy;
    R[2][1] = tyz + twx;
    R[2][2] = 1 - (txx + tyy);
}

namespace {

/// The share of an entry under water, for drag and wetted area (kernels/buoyancy.cl wetShare).
double wetShare(double depth, const Vec3& a, double area) {
    const double length2 = dot(a, a);
    const double upright = length2 > 0 ? a.y * a.y / length2 : 1.0;
    const double extent = std::sqrt(area * std::max(0.0, 1.0 - upright));
    if (extent <= 0) return depth > 0 ? 1.0 : 0.0;
    return std::clamp(0.5 + depth / extent, 0.0, 1.0);
}

}  // namespace

Forces Bundle::evaluate(const Pose& pose, const Velocity& velocity, const Water& water,
                        const Fluid& fluid, double time) const {
    double R[3][3];
    rotationMatrix(pose.orientation, R);
    const Vec3 com = mass_.centerOfMass;
    const Vec3 c = mul(R, com) + pose.position;
    const double rhoG = fluid.density * fluid.gravity;
    const double halfRhoCd = 0.5 * fluid.density * fluid.dragCoefficient;
    const double halfRhoCf = 0.5 * fluid.density * fluid.frictionCoefficient;
    double volume = 0;
    Vec3 moment, pressureF, pressureT, dragF, dragT;
    double wetted = 0;
    std::size_t count = 0;
    for (const Sample& s : samples_) {
        const Vec3 r = mul(R, s.position - com);
        const Vec3 world = c + r;
        const double f = water.heightAt(world.x, world.z, time) - c.y;
        const double depth = f - r.y;
        const Vec3 a = mul(R, s.areaVector);
        const double wet = wetShare(depth, a, s.area);
        if (wet <= 0) continue;
        if (depth > 0) {
            volume -= a.y * depth;
            moment.x -= a.y * r.x * depth;
            moment.y += a.y * 0.5 * (r.y * r.y - f * f);
            moment.z -= a.y * r.z * depth;
            const Vec3 force = -(rhoG * depth) * a;
            pressureF += force;
            pressureT += cross(r, force);
            ++count;
        }
        wetted += wet * s.area;
        Vec3 v = velocity.linear + cross(velocity.angular, r);
        if (water.velocity) v -= water.velocity(world, time);
        const double speed = norm(v);
        Vec3 drag;
        if (speed > 0) {
            const double facing = dot(a, v) / speed;
            if (facing > 0) drag -= (wet * halfRhoCd * facing * speed) * v;
            if (halfRhoCf > 0 && s.area > 0) {
                const Vec3 n = (1.0 / std::max(norm(a), 1e-30)) * a;
                const Vec3 tangential = v - dot(v, n) * n;
                drag -= (wet * halfRhoCf * s.area * norm(tangential)) * tangential;
            }
        }
        dragF += drag;
        dragT += cross(r, drag);
    }
    Forces out;
    out.submergedVolume = volume;
    out.centerOfBuoyancy = c;
    // A body that only grazes the water can sum to a volume of zero or slightly below: no
    // Archimedes force then, and no division by it (as the engine).
    if (volume > 0 && std::isfinite(volume)) {
        const Vec3 offset{moment.x / volume, moment.y / volume, moment.z / volume};
        if (finite(offset)) out.centerOfBuoyancy = c + offset;
        out.force = {0, fluid.density * fluid.gravity * volume, 0};
        out.torque = cross(out.centerOfBuoyancy - c, out.force);
    }
    out.pressureForce = pressureF;
    out.pressureTorque = pressureT;
    out.dragForce = dragF;
    out.dragTorque = dragT;
    out.wettedArea = wetted;
    out.submergedSamples = count;
    return out;
}

}  // namespace plimsoll_runtime
