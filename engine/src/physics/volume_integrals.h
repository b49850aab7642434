// Internal: the ten volume (or mass) integrals every mass-property method reduces to, and
// their conversion into MassProperties. Shared by the exact mesh path and the texture path so
// the two differ only in how the integrals are computed.
#pragma once

#include "plimsoll/physics/massprops.h"

namespace plimsoll::detail {

/// Integrals over the body of 1, x, y, z, x^2, y^2, z^2, xy, yz, zx, with (x, y, z) measured
/// from `reference` (object space). Units: m^3 .. m^5 for volumes, kg .. kg m^2 for masses.
struct BodyIntegrals {
    Eigen::Vector3d reference = Eigen::Vector3d::Zero();
    double zeroth = 0;
    Eigen::Vector3d first = Eigen::Vector3d::Zero();
    /// Symmetric matrix of second moments: integral of r r^T.
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
};

/// Mass properties of a body whose mass integrals are `density` times `integrals`.
/// `volume` is stored as given (the enclosed volume, whatever carries the mass).
MassProperties toMassProperties(const BodyIntegrals& integrals, double density, double volume);

}  // namespace plimsoll::detail
