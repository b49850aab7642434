// Mass properties from the baked textures (paper section 3.1; the corrected integrands are in
// docs/design.md, "Mass properties"). Each volume integral becomes a flux integral of a field
// whose divergence is the integrand, and the flux integral a sum over texels of A_i . F(p_i):
//   V          = sum A_y y
//   int x dV   = sum A_x x^2/2   (y, z alike)
//   int x^2 dV = sum A_x x^3/3   (y, z alike)
//   int xy dV  = sum A_x x^2 y/2,  int yz dV = sum A_y y^2 z/2,  int zx dV = sum A_z z^2 x/2
// Positions are taken relative to the surface's area centroid so that bodies far from the
// origin do not lose digits to cancellation.
#include "plimsoll/bake/bake.h"
#include "plimsoll/physics/massprops.h"

#include "physics/volume_integrals.h"

namespace plimsoll {

MassProperties textureSolidMassProperties(const SurfaceTextures& textures, double density) {
    detail::BodyIntegrals body;
    body.reference = textures.areaCentroid();
    double xx = 0, yy = 0, zz = 0, xy = 0, yz = 0, zx = 0;
    for (std::size_t i = 0; i < textures.coveredCount(); ++i) {
        const Eigen::Vector3d p = textures.position[i] - body.reference;
        const Eigen::Vector3d& a = textures.areaVector[i];
        const double x = p.x(), y = p.y(), z = p.z();
        body.zeroth += a.y() * y;
        body.first += Eigen::Vector3d(a.x() * x * x, a.y() * y * y, a.z() * z * z);
        xx += a.x() * x * x * x;
        yy += a.y() * y * y * y;
        zz += a.z() * z * z * z;
        xy += a.x() * x * x * y;
        yz += a.y() * y * y * z;
        zx += a.z() * z * z * x;
    }
    body.first /= 2.0;
    xx /= 3.0, yy /= 3.0, zz /= 3.0;
    xy /= 2.0, yz /= 2.0, zx /= 2.0;
    body.second << xx, xy, zx, xy, yy, yz, zx, yz, zz;
    return detail::toMassProperties(body, density, body.zeroth);
}

MassProperties textureShellMassProperties(const SurfaceTextures& textures,
                                          double uniformSurfaceDensity,
                                          const std::vector<double>& surfaceDensity) {
    const bool painted = !surfaceDensity.empty();
    detail::BodyIntegrals mass;
    mass.reference = textures.areaCentroid();
    double volume = 0;
    for (std::size_t i = 0; i < textures.coveredCount(); ++i) {
        const Eigen::Vector3d p = textures.position[i] - mass.reference;
        const double m = (painted ? surfaceDensity[i] : uniformSurfaceDensity) * textures.area[i];
        mass.zeroth += m;
        mass.first += m * p;
        mass.second += m * p * p.transpose();
        volume += textures.areaVector[i].y() * p.y();
    }
    // The integrals already carry the density: unit factor.
    return detail::toMassProperties(mass, 1.0, volume);
}

}  // namespace plimsoll
