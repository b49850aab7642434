// Exact mass properties of a closed triangle mesh.
// Solid: Eberly, "Polyhedral Mass Properties (Revisited)" (2002), itself a simplification of
// Mirtich, "Fast and Accurate Computation of Polyhedral Mass Properties" (1996): the
// divergence theorem turns each volume integral into exact polynomial integrals over the
// triangles.
// Shell: each triangle a uniform lamina, integral of r r^T dS = (a/12)(sum v v^T + s s^T).
#include "plimsoll/physics/massprops.h"

#include "physics/volume_integrals.h"

#include <Eigen/Geometry>

#include <algorithm>

namespace plimsoll {

namespace detail {

MassProperties toMassProperties(const BodyIntegrals& integrals, double density, double volume) {
    MassProperties result;
    result.volume = volume;
    result.mass = density * integrals.zeroth;
    if (integrals.zeroth == 0.0) {
        result.centerOfMass = integrals.reference;
        return result;
    }
    const Eigen::Vector3d offset = integrals.first / integrals.zeroth;
    // Second moments about the centre of mass (parallel-axis theorem), then I = tr(S) Id - S.
    const Eigen::Matrix3d central =
        integrals.second - integrals.zeroth * offset * offset.transpose();
    result.centerOfMass = integrals.reference + offset;
    result.inertia = density * (central.trace() * Eigen::Matrix3d::Identity() - central);
    return result;
}

}  // namespace detail

namespace {

// Eberly's subexpressions for one coordinate of a triangle's three vertices.
struct Subexpressions {
    double f1, f2, f3, g0, g1, g2;
};

Subexpressions subexpressions(double w0, double w1, double w2) {
    Subexpressions s;
    const double temp0 = w0 + w1;
    s.f1 = temp0 + w2;
    const double temp1 = w0 * w0;
    const double temp2 = temp1 + w1 * temp0;
    s.f2 = temp2 + w2 * s.f1;
    s.f3 = w0 * temp1 + w1 * temp2 + w2 * s.f2;
    s.g0 = s.f2 + w0 * (s.f1 + w0);
    s.g1 = s.f2 + w1 * (s.f1 + w1);
    s.g2 = s.f2 + w2 * (s.f1 + w2);
    return s;
}

detail::BodyIntegrals exactVolumeIntegrals(const TriangleMesh& mesh) {
    detail::BodyIntegrals out;
    out.reference = computeBounds(mesh).center();
    // intg: 1, x, y, z, x^2, y^2, z^2, xy, yz, zx (Eberly's order), before the 1/6.. factors.
    double intg[10] = {};
    for (const Triangle& t : mesh.triangles) {
        const Eigen::Vector3d p0 = mesh.positions[t[0]] - out.reference;
        const Eigen::Vector3d p1 = mesh.positions[t[1]] - out.reference;
        const Eigen::Vector3d p2 = mesh.positions[t[2]] - out.reference;
        const Eigen::Vector3d d = (p1 - p0).cross(p2 - p0);
        const Subexpressions sx = subexpressions(p0.x(), p1.x(), p2.x());
        const Subexpressions sy = subexpressions(p0.y(), p1.y(), p2.y());
        const Subexpressions sz = subexpressions(p0.z(), p1.z(), p2.z());
        intg[0] += d.x() * sx.f1;
        intg[1] += d.x() * sx.f2;
        intg[2] += d.y() * sy.f2;
        intg[3] += d.z() * sz.f2;
        intg[4] += d.x() * sx.f3;
        intg[5] += d.y() * sy.f3;
        intg[6] += d.z() * sz.f3;
        intg[7] += d.x() * (p0.y() * sx.g0 + p1.y() * sx.g1 + p2.y() * sx.g2);
        intg[8] += d.y() * (p0.z() * sy.g0 + p1.z() * sy.g1 + p2.z() * sy.g2);
        intg[9] += d.z() * (p0.x() * sz.g0 + p1.x() * sz.g1 + p2.x() * sz.g2);
    }
    out.zeroth = intg[0] / 6.0;
    out.first = Eigen::Vector3d(intg[1], intg[2], intg[3]) / 24.0;
    const double xx = intg[4] / 60.0, yy = intg[5] / 60.0, zz = intg[6] / 60.0;
    const double xy = intg[7] / 120.0, yz = intg[8] / 120.0, zx = intg[9] / 120.0;
    out.second << xx, xy, zx, xy, yy, yz, zx, yz, zz;
    return out;
}

}  // namespace

MassProperties operator+(const MassProperties& a, const MassProperties& b) {
    MassProperties sum;
    sum.mass = a.mass + b.mass;
    sum.volume = std::max(a.volume, b.volume);
    if (sum.mass == 0.0) {
        sum.centerOfMass = 0.5 * (a.centerOfMass + b.centerOfMass);
        return sum;
    }
    sum.centerOfMass = (a.mass * a.centerOfMass + b.mass * b.centerOfMass) / sum.mass;
    // Parallel-axis theorem: I_c = I_own + m (|d|^2 Id - d d^T), d from the new centre.
    auto shifted = [&](const MassProperties& part) {
        const Eigen::Vector3d d = part.centerOfMass - sum.centerOfMass;
        return Eigen::Matrix3d(
            part.inertia +
            part.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
    };
    sum.inertia = shifted(a) + shifted(b);
    return sum;
}

MassProperties operator-(const MassProperties& a, const MassProperties& b) {
    MassProperties negative = b;
    negative.mass = -b.mass;
    negative.inertia = -b.inertia;
    MassProperties difference = a + negative;
    difference.volume = a.volume;
    return difference;
}

MassProperties withoutHollow(const MassProperties& solid, const MassProperties& hollow,
                             double density) {
    if (!(hollow.mass > 0)) return solid;
    MassProperties filled = hollow;
    filled.mass *= density;
    filled.inertia *= density;
    return solid - filled;
}

MassProperties exactSolidMassProperties(const TriangleMesh& mesh, double density) {
    const detail::BodyIntegrals integrals = exactVolumeIntegrals(mesh);
    return detail::toMassProperties(integrals, density, integrals.zeroth);
}

MassProperties exactShellMassProperties(const TriangleMesh& mesh, double surfaceDensity) {
    detail::BodyIntegrals area;
    area.reference = computeBounds(mesh).center();
    for (const Triangle& t : mesh.triangles) {
        const Eigen::Vector3d p0 = mesh.positions[t[0]] - area.reference;
        const Eigen::Vector3d p1 = mesh.positions[t[1]] - area.reference;
        const Eigen::Vector3d p2 = mesh.positions[t[2]] - area.reference;
        const double a = 0.5 * (p1 - p0).cross(p2 - p0).norm();
        const Eigen::Vector3d s = p0 + p1 + p2;
        area.zeroth += a;
        area.first += a * s / 3.0;
        area.second += (a / 12.0) * (p0 * p0.transpose() + p1 * p1.transpose() +
                                     p2 * p2.transpose() + s * s.transpose());
    }
    const double volume = exactVolumeIntegrals(mesh).zeroth;
    return detail::toMassProperties(area, surfaceDensity, volume);
}

}  // namespace plimsoll
