// Exact buoyancy of a closed triangle mesh under planar water y = level: the reference that the
// texel sums are held against on flat water.
// Every triangle is clipped against the water plane and the part below is kept, as Jolt
// Physics' buoyancy and J. Kerner, "Water interaction model for boats in video games"
// (Gamasutra, 2015) do. Over the kept pieces the divergence theorem turns the submerged volume
// and its first moments into surface integrals of vector fields that vanish on the water plane
// (docs/design.md, "Buoyancy"), so the cap where the plane cuts the body contributes nothing
// and needs no polygon. On a planar piece each integrand is a polynomial of degree at most
// two, which the three-edge-midpoint rule integrates exactly.
#include "plimsoll/physics/buoyancy.h"

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <vector>

namespace plimsoll {

namespace {

/// Integrals over the wetted pieces, with positions relative to the body's centre of mass.
struct WettedSums {
    double volume = 0;                                         ///< m^3
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();          ///< first moment of volume, m^4
    Eigen::Vector3d pressureForce = Eigen::Vector3d::Zero();   ///< N
    Eigen::Vector3d pressureTorque = Eigen::Vector3d::Zero();  ///< N m
    double wettedArea = 0;                                     ///< m^2
};

/// Adds the wetted triangle (a, b, c) (m, relative to the centre of mass, all at or below the
/// water height h) to the sums. rhoG: fluid density times gravity, N/m^3.
void addPiece(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
              double h, double rhoG, WettedSums& sums) {
    const Eigen::Vector3d area = 0.5 * (b - a).cross(c - a);  // outward, m^2
    const std::array<Eigen::Vector3d, 3> midpoints = {0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)};
    double height = 0;                                // mean of y - h, m (<= 0)
    Eigen::Vector3d field = Eigen::Vector3d::Zero();  // mean of the moment fields' y parts, m^2
    double pressure = 0;                              // mean of p, Pa
    Eigen::Vector3d pressureLever = Eigen::Vector3d::Zero();  // mean of p r, Pa m
    for (const Eigen::Vector3d& m : midpoints) {
        const double below = m.y() - h;
        height += below;
        // (y^2 - h^2)/2 factored, so no digits are lost when y and h are close.
        field += Eigen::Vector3d(m.x() * below, 0.5 * below * (m.y() + h), m.z() * below);
        const double p = -rhoG * below;
        pressure += p;
        pressureLever += p * m;
    }
    height /= 3.0;
    field /= 3.0;
    pressure /= 3.0;
    pressureLever /= 3.0;

    sums.volume += area.y() * height;
    sums.moment += area.y() * field;
    sums.pressureForce -= pressure * area;
    // Integral of r x (-p n) dS over a planar piece = -(mean of p r) x A.
    sums.pressureTorque -= pressureLever.cross(area);
    sums.wettedArea += area.norm();
}

/// Clips the triangle (p[0], p[1], p[2]) to y <= h and adds the kept part (none, a triangle or a
/// quadrilateral split in two, same winding) to the sums.
void addClipped(const std::array<Eigen::Vector3d, 3>& p, double h, double rhoG, WettedSums& sums) {
    std::array<Eigen::Vector3d, 4> polygon;  // a half-plane cuts at most one corner off
    int count = 0;
    for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d& a = p[i];
        const Eigen::Vector3d& b = p[(i + 1) % 3];
        const double da = a.y() - h;
        const double db = b.y() - h;
        if (da <= 0.0) polygon[count++] = a;
        // A crossing only where the ends lie strictly on opposite sides: the division is then
        // safe, and a vertex on the plane is kept once, as itself.
        if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
            // From the submerged end, so the two triangles sharing the edge get the same point.
            const Eigen::Vector3d& wet = da < 0.0 ? a : b;
            const Eigen::Vector3d& dry = da < 0.0 ? b : a;
            const double dWet = wet.y() - h;
            const double dDry = dry.y() - h;
            Eigen::Vector3d crossing = wet + (dWet / (dWet - dDry)) * (dry - wet);
            crossing.y() = h;  // on the plane exactly, where the fields vanish
            polygon[count++] = crossing;
        }
    }
    if (count >= 3) addPiece(polygon[0], polygon[1], polygon[2], h, rhoG, sums);
    if (count == 4) addPiece(polygon[0], polygon[2], polygon[3], h, rhoG, sums);
}

}  // namespace

BuoyancyResult evaluateBuoyancyExact(const TriangleMesh& mesh, const BodyFrame& frame,
                                     double waterLevel, const FluidSettings& fluid) {
    const Eigen::Vector3d center = frame.pose.apply(frame.centerOfMass);  // world, m
    BuoyancyResult result;
    result.centerOfBuoyancy = center;

    // Work relative to the centre of mass: R (p - com) is pose.apply(p) - center without ever
    // forming world coordinates, so a body 1e5 m from the origin keeps its digits.
    const double h = waterLevel - center.y();  // water height above the centre of mass, m
    std::vector<Eigen::Vector3d> relative(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        relative[i] = frame.pose.rotation * (mesh.positions[i] - frame.centerOfMass);
    }

    const double rhoG = fluid.density * fluid.gravity;  // N/m^3
    WettedSums sums;
    for (const Triangle& t : mesh.triangles) {
        addClipped({relative[t[0]], relative[t[1]], relative[t[2]]}, h, rhoG, sums);
    }
    // Dry (or a degenerate mesh): no force, and the centre of buoyancy stays at the centre of
    // mass as the header promises.
    if (!std::isfinite(sums.volume) || sums.volume <= 0.0) return result;

    const Eigen::Vector3d offset = sums.moment / sums.volume;  // C_B - c, m
    result.submergedVolume = sums.volume;
    result.centerOfBuoyancy = center + offset;
    result.force = Eigen::Vector3d(0.0, rhoG * sums.volume, 0.0);
    result.torque = offset.cross(result.force);
    result.pressureForce = sums.pressureForce;
    result.pressureTorque = sums.pressureTorque;
    result.wettedArea = sums.wettedArea;
    return result;
}

}  // namespace plimsoll
