// Per-frame hydrostatics and drag of a body under a height-field water surface
// (docs/design.md, "Buoyancy"). With fields that vanish on the water surface every formula is
// exact for any height field and needs no cap polygon:
//   submerged volume  V_s = sum_sub A_y (y - f)                           (paper eq. 10)
//   first moments     sum_sub A_y x (y - f), sum_sub A_y (y^2 - f^2)/2, sum_sub A_y z (y - f)
//   pressure          p_i = rho g (f_i - y_i),  F = -sum p_i A_i,  T = sum (p_i - c) x (-p_i A_i)
//   drag              D_i = -1/2 rho C_d max(0, A_i.v_i/|v_i|) |v_i| v_i
#pragma once

#include "plimsoll/geometry/mesh.h"
#include "plimsoll/physics/pose.h"
#include "plimsoll/physics/water.h"

#include <Eigen/Core>

#include <cstddef>

namespace plimsoll {

struct SurfaceTextures;

/// The fluid around the body and how it acts.
struct FluidSettings {
    double density = 1000.0;            ///< kg/m^3 (fresh water; sea 1025, air 1.225)
    double gravity = kStandardGravity;  ///< m/s^2, acting along -y
    double dragCoefficient = 1.0;       ///< C_d of pressure drag, dimensionless
    double frictionCoefficient = 0.0;   ///< C_f of skin friction; 0 = off
};

/// Everything a frame needs from the water: forces in world axes, torques about the body's
/// centre of mass.
struct BuoyancyResult {
    double submergedVolume = 0;                                  ///< m^3
    Eigen::Vector3d centerOfBuoyancy = Eigen::Vector3d::Zero();  ///< world, m (= centre of
                                                                 ///< mass when dry)
    Eigen::Vector3d force = Eigen::Vector3d::Zero();             ///< Archimedes: rho g V_s up, N
    Eigen::Vector3d torque = Eigen::Vector3d::Zero();            ///< (C_B - c) x force, N m
    Eigen::Vector3d pressureForce = Eigen::Vector3d::Zero();     ///< -sum p_i A_i, N
    Eigen::Vector3d pressureTorque = Eigen::Vector3d::Zero();    ///< N m
    Eigen::Vector3d dragForce = Eigen::Vector3d::Zero();         ///< N
    Eigen::Vector3d dragTorque = Eigen::Vector3d::Zero();        ///< N m
    double wettedArea = 0;                                       ///< m^2
    std::size_t submergedSamples = 0;                            ///< texel entries under water
};

/// The state of one body for one evaluation.
struct BodyFrame {
    Pose pose;                                               ///< object -> world
    Motion motion;                                           ///< of the centre of mass
    Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();  ///< object space, m
    double time = 0;                                         ///< s, for moving water
};

/// The C++ reference (double precision, every entry, no culling): the oracle the kernels are
/// tested against, and the path that runs where no OpenCL device exists.
BuoyancyResult evaluateBuoyancyReference(const SurfaceTextures& textures, const BodyFrame& frame,
                                         const WaterModel& water, const FluidSettings& fluid);

/// The exact reference for planar water y = level: the triangle mesh clipped against the plane
/// (as Jolt and Kerner do), with the same fields, integrated exactly per triangle. Fills
/// submergedVolume, centerOfBuoyancy, force, torque, pressureForce, pressureTorque,
/// wettedArea; drag stays zero.
BuoyancyResult evaluateBuoyancyExact(const TriangleMesh& mesh, const BodyFrame& frame,
                                     double waterLevel, const FluidSettings& fluid);

}  // namespace plimsoll
