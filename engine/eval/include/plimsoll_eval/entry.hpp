// What one surface entry (a texel's area centroid p, outward area vector A, area |S|)
// contributes to a body's sums under a height-field water surface y = f(x, z), and how the
// sums become forces. With fields that vanish on the surface every sum is exact for any
// height field (docs/design.md, "Buoyancy under a height-field water surface"):
//   volume  V = sum_sub -A_y d  (d = f - y, the depth),   moments sum_sub -A_y r_x d, ...
//   pressure F = -sum rho g d A,  drag D = -1/2 rho C_d w max(0, A.v/|v|) |v| v
// where w is the entry's wetted share (wetShare). All quantities are relative to the body's
// centre c (world axes), so single precision keeps its digits wherever the body is.
#pragma once

#include "plimsoll_eval/vec.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace plimsoll_eval {

/// The fluid constants the sums need.
struct Coefficients {
    double rhoG = 1000.0 * 9.81;  ///< rho g, N/m^3
    double halfRhoCd = 500.0;     ///< rho C_d / 2, kg/m^3
    double halfRhoCf = 0.0;       ///< rho C_f / 2 (skin friction; 0 = off)
};

/// One body's sums (double: they add thousands of entries of either sign).
struct Sums {
    double volume = 0;      ///< m^3
    Vec3 moment;            ///< first moments of the submerged volume about c, m^4
    Vec3 pressureForce;     ///< N
    Vec3 pressureTorque;    ///< N m, about c
    Vec3 dragForce;         ///< N
    Vec3 dragTorque;        ///< N m, about c
    double wettedArea = 0;  ///< m^2
    double count = 0;       ///< submerged entries

    Sums& operator+=(const Sums& o) {
        volume += o.volume;
        moment += o.moment;
        pressureForce += o.pressureForce;
        pressureTorque += o.pressureTorque;
        dragForce += o.dragForce;
        dragTorque += o.dragTorque;
        wettedArea += o.wettedArea;
        count += o.count;
        return *this;
    }
};

/// The share of an entry under water, for drag and wetted area: the entry is taken as a flat
/// patch of side sqrt(area) tilted like its area vector, cut by the surface at `depth` below
/// it; an upright (horizontal) patch is wholly in or out. `upright` is A_y^2 / |A|^2 (1 for a
/// zero area vector), which each caller computes in its own way (wetShare below multiplies by
/// a stored 1 / |A|^2; the double-precision reference divides). Written without branches, so
/// that a loop over entries vectorises.
template <class T>
inline T wetShareOfUpright(T depth, T upright, T area) {
    const T tilt = T(1) - upright;
    const T extent = std::sqrt(area * (tilt > 0 ? tilt : T(0)));
    const T share = T(0.5) + depth / (extent > 0 ? extent : T(1));
    const T partial = share < T(0) ? T(0) : (share > T(1) ? T(1) : share);
    return extent > 0 ? partial : (depth > 0 ? T(1) : T(0));
}

/// wetShare with `inverseLength2` = 1 / |A|^2 (0 for a zero area vector).
template <class T>
inline T wetShare(T depth, T ay, T area, T inverseLength2) {
    return wetShareOfUpright(depth, inverseLength2 > 0 ? ay * ay * inverseLength2 : T(1), area);
}

/// What one entry adds to each sum (the slots of Sums, flat; its forces and torques in the
/// frame entryTerms was given them in).
template <class T>
struct EntryTerms {
    T volume, moment[3], pressureForce[3], pressureTorque[3], dragForce[3], dragTorque[3];
    T wettedArea, count;
};

/// One entry's drag (force, and torque about c) with `wet` its wetted share (see entryTerms).
template <class T, bool Friction>
inline void entryDrag(const T r[3], const T a[3], T area, T inverseLength, T wet, const T v[3],
                      T halfRhoCd, T halfRhoCf, T force[3], T torque[3]) {
    // Pressure drag on the entries facing the flow: (A.v/|v|) |v| v = (A.v) v.
    const T facing = a[0] * v[0] + a[1] * v[1] + a[2] * v[2];
    const T s = facing > 0 ? wet * halfRhoCd * facing : T(0);
    for (int i = 0; i < 3; ++i) force[i] = -s * v[i];
    if (Friction) {
        const T n[3] = {a[0] * inverseLength, a[1] * inverseLength, a[2] * inverseLength};
        const T along = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
        const T t[3] = {v[0] - along * n[0], v[1] - along * n[1], v[2] - along * n[2]};
        const T g = wet * halfRhoCf * area * std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        for (int i = 0; i < 3; ++i) force[i] -= g * t[i];
    }
    torque[0] = r[1] * force[2] - r[2] * force[1];
    torque[1] = r[2] * force[0] - r[0] * force[2];
    torque[2] = r[0] * force[1] - r[1] * force[0];
}

/// One entry seen in two frames: the water's (world axes: r its position relative to c, ay its
/// area vector's vertical component), which decides its depth, wetted share, volume and
/// moments; and any one frame for the rest (q, b its position and area vector, v its velocity
/// relative to the water), in which its pressure and drag forces and torques come out. `area`
/// is its surface area, f the water height above it (relative to c.y). `inverseLength2` = 1 /
/// |b|^2 and `inverseLength` = 1 / max(|b|, 1e-30) are properties of the entry (a rotation
/// keeps them). The fast path takes the body's own axes for the second frame: a per-entry loop
/// then rotates the position alone (the forces' sums are turned once, after the loop).
/// Branch-free: every term is selected.
template <class T, bool Friction>
inline EntryTerms<T> entryTerms(const T r[3], T ay, const T q[3], const T b[3], T area,
                                T inverseLength2, T inverseLength, T f, const T v[3], T rhoG,
                                T halfRhoCd, T halfRhoCf) {
    EntryTerms<T> e;
    const T depth = f - r[1];
    const T wet = wetShare(depth, ay, area, inverseLength2);
    const T under = depth > 0 ? T(1) : T(0);
    const T d = under * depth;
    e.volume = -ay * d;
    e.moment[0] = -ay * r[0] * d;
    e.moment[1] = under * ay * T(0.5) * (r[1] * r[1] - f * f);
    e.moment[2] = -ay * r[2] * d;
    const T p = rhoG * d;
    for (int i = 0; i < 3; ++i) e.pressureForce[i] = -p * b[i];
    e.pressureTorque[0] = q[1] * e.pressureForce[2] - q[2] * e.pressureForce[1];
    e.pressureTorque[1] = q[2] * e.pressureForce[0] - q[0] * e.pressureForce[2];
    e.pressureTorque[2] = q[0] * e.pressureForce[1] - q[1] * e.pressureForce[0];
    e.count = under;
    e.wettedArea = wet * area;
    entryDrag<T, Friction>(q, b, area, inverseLength, wet, v, halfRhoCd, halfRhoCf, e.dragForce,
                           e.dragTorque);
    return e;
}

/// A body's forces from its sums: world axes, torques about c.
struct Forces {
    double submergedVolume = 0;  ///< m^3
    Vec3 centerOfBuoyancy;       ///< world, m (= c when dry)
    Vec3 force;                  ///< Archimedes: rho g V up, N
    Vec3 torque;                 ///< (C_B - c) x force, N m
    Vec3 pressureForce, pressureTorque, dragForce, dragTorque;
    double wettedArea = 0;  ///< m^2
    std::size_t submergedSamples = 0;
};

/// `c` the body's centre in world coordinates; `rhoG` rho g.
inline Forces finish(const Sums& sums, const Vec3& c, double rhoG) {
    Forces out;
    out.submergedVolume = sums.volume;
    out.centerOfBuoyancy = c;
    // A body that only grazes the water can sum to a volume of zero or, by discretisation,
    // slightly below: no Archimedes force then, and no division by it.
    if (sums.volume > 0 && std::isfinite(sums.volume)) {
        const Vec3 offset = (1.0 / sums.volume) * sums.moment;
        if (finite(offset)) out.centerOfBuoyancy = c + offset;
        out.force = {0, rhoG * sums.volume, 0};
        out.torque = cross(out.centerOfBuoyancy - c, out.force);
    }
    out.pressureForce = sums.pressureForce;
    out.pressureTorque = sums.pressureTorque;
    out.dragForce = sums.dragForce;
    out.dragTorque = sums.dragTorque;
    out.wettedArea = sums.wettedArea;
    out.submergedSamples = static_cast<std::size_t>(std::llround(sums.count));
    return out;
}

}  // namespace plimsoll_eval
