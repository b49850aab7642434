// The C++ reference of kernels/buoyancy.cl: the same sums in double precision over every
// entry, without tile culling. See buoyancy.h for the formulas (docs/design.md, "Buoyancy").
#include "plimsoll/bake/bake.h"
#include "plimsoll/physics/buoyancy.h"

#include "physics/buoyancy_sums.h"
#include "plimsoll_eval/entry.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace plimsoll {

namespace detail {

BuoyancyResult finishBuoyancy(const BuoyancySums& sums, const Eigen::Vector3d& centerOfMass,
                              const FluidSettings& fluid) {
    auto vec = [&](int slot) {
        return Eigen::Vector3d(sums[slot], sums[slot + 1], sums[slot + 2]);
    };
    BuoyancyResult r;
    r.submergedVolume = sums[PL_SUM_VOLUME];
    r.centerOfBuoyancy = centerOfMass;
    // A body that only grazes the water can sum to a volume of zero or, by discretisation,
    // slightly below: no Archimedes force then, and no division by it.
    if (r.submergedVolume > 0 && std::isfinite(r.submergedVolume)) {
        const Eigen::Vector3d offset = vec(PL_SUM_MOMENT) / r.submergedVolume;
        if (offset.allFinite()) r.centerOfBuoyancy = centerOfMass + offset;
        r.force = Eigen::Vector3d(0, fluid.density * fluid.gravity * r.submergedVolume, 0);
        r.torque = (r.centerOfBuoyancy - centerOfMass).cross(r.force);
    }
    r.pressureForce = vec(PL_SUM_PRESSURE_F);
    r.pressureTorque = vec(PL_SUM_PRESSURE_T);
    r.dragForce = vec(PL_SUM_DRAG_F);
    r.dragTorque = vec(PL_SUM_DRAG_T);
    r.wettedArea = sums[PL_SUM_WETTED_AREA];
    r.submergedSamples = static_cast<std::size_t>(std::llround(sums[PL_SUM_COUNT]));
    return r;
}

}  // namespace detail

BuoyancyResult evaluateBuoyancyReference(const SurfaceTextures& textures, const BodyFrame& frame,
                                         const WaterModel& water, const FluidSettings& fluid) {
    const Eigen::Matrix3d& R = frame.pose.rotation;
    const Eigen::Vector3d c = frame.pose.apply(frame.centerOfMass);
    const double rhoG = fluid.density * fluid.gravity;
    const double halfRhoCd = 0.5 * fluid.density * fluid.dragCoefficient;
    const double halfRhoCf = 0.5 * fluid.density * fluid.frictionCoefficient;
    detail::BuoyancySums sum{};
    for (std::size_t i = 0; i < textures.coveredCount(); ++i) {
        const Eigen::Vector3d r = R * (textures.position[i] - frame.centerOfMass);
        const Eigen::Vector3d world = c + r;
        const double f = water.height(world.x(), world.z(), frame.time) - c.y();
        const double depth = f - r.y();
        const Eigen::Vector3d a = R * textures.areaVector[i];
        const double length2 = a.squaredNorm();
        const double wet = plimsoll_eval::wetShareOfUpright(
            depth, length2 > 0 ? a.y() * a.y() / length2 : 1.0, textures.area[i]);
        if (wet <= 0) continue;
        if (depth > 0) {
            sum[PL_SUM_VOLUME] -= a.y() * depth;
            sum[PL_SUM_MOMENT + 0] -= a.y() * r.x() * depth;
            sum[PL_SUM_MOMENT + 1] += a.y() * 0.5 * (r.y() * r.y() - f * f);
            sum[PL_SUM_MOMENT + 2] -= a.y() * r.z() * depth;
            const Eigen::Vector3d pressureForce = -(rhoG * depth) * a;
            const Eigen::Vector3d pressureTorque = r.cross(pressureForce);
            for (int k = 0; k < 3; ++k) {
                sum[PL_SUM_PRESSURE_F + k] += pressureForce[k];
                sum[PL_SUM_PRESSURE_T + k] += pressureTorque[k];
            }
            sum[PL_SUM_COUNT] += 1;
        }
        sum[PL_SUM_WETTED_AREA] += wet * textures.area[i];
        const Eigen::Vector3d v =
            frame.motion.linear + frame.motion.angular.cross(r) - water.velocity(world, frame.time);
        const double speed = v.norm();
        Eigen::Vector3d drag = Eigen::Vector3d::Zero();
        if (speed > 0) {
            const double facing = a.dot(v) / speed;
            if (facing > 0) drag -= (wet * halfRhoCd * facing * speed) * v;
            if (halfRhoCf > 0 && textures.area[i] > 0) {
                const Eigen::Vector3d n = a / std::max(a.norm(), 1e-30);
                const Eigen::Vector3d tangential = v - v.dot(n) * n;
                drag -= (wet * halfRhoCf * textures.area[i] * tangential.norm()) * tangential;
            }
        }
        const Eigen::Vector3d dragTorque = r.cross(drag);
        for (int k = 0; k < 3; ++k) {
            sum[PL_SUM_DRAG_F + k] += drag[k];
            sum[PL_SUM_DRAG_T + k] += dragTorque[k];
        }
    }
    return detail::finishBuoyancy(sum, c, fluid);
}

}  // namespace plimsoll
