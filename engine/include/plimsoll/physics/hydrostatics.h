// Hydrostatics and stability of a floating body in calm water (docs/hydrostatics.md): the
// equilibrium draft, trim and heel for the body's mass, the waterplane, the metacentric
// heights and the righting-arm curve GZ from 0 to 180 degrees. Axes are the body's object
// axes with y up: heel is a rotation about x, trim about z.
//
// Two measures of the displaced water, both the engine's own buoyancy evaluations on flat
// water: the texel sums over the baked textures (what the simulation feels) and the exact clip
// of the triangle mesh (the reference). Every figure is derived from the displaced volume and
// its centre; the exact clip's waterplane comes from their derivatives
//   waterplane area     A_wp = dV/dh                       (h: the water's height)
//   centre of flotation x_F  = d(V x_B)/dh / A_wp
//   metacentric height  GM   = dGZ/dphi at phi = 0, constant displacement
//   metacentric radius  BM   = GM - (z_G - z_B)             (= I_wp / V)
// and the textures' from flux sums over the submerged entries, A_wp = -sum A_y,
// I_wp = -sum A_y (z - z_F)^2 (each entry's own second moment added), BM = I_wp / V.
#pragma once

#include "plimsoll/core/result.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/physics/water.h"

#include <Eigen/Core>

#include <vector>

namespace plimsoll {

struct SurfaceTextures;
struct WaterGraph;

/// A free surface inside the body: the water of a partly filled compartment, which moves to
/// the low side as the body heels and so lowers the effective GM by rho_t i / (rho V).
struct FreeSurface {
    double density = 1000.0;     ///< of the liquid in the compartment, kg/m^3
    double inertiaAboutX = 0;    ///< second moment of the surface about its own x axis, m^4
    double inertiaAboutZ = 0;    ///< about its own z axis, m^4
};

/// What floats: its mass and where it acts, the water it carries included.
struct HydrostaticBody {
    double mass = 0;                                       ///< kg, > 0
    Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();  ///< object space, m
    std::vector<FreeSurface> freeSurfaces;                 ///< partly filled compartments
};

struct HydrostaticsSettings {
    double density = 1000.0;             ///< of the water the body floats in, kg/m^3
    double gravity = kStandardGravity;   ///< m/s^2 (enters only through the weight)
    double gzStepDegrees = 5.0;          ///< spacing of the GZ curve, 0 < step <= 90
    /// Heel and trim step of the exact clip's metacentric derivatives: Richardson's
    /// extrapolation over this step and twice it cancels the tan^2 term of the wall-sided
    /// curve.
    double derivativeStepDegrees = 1.0;
};

enum class HydrostaticsMethod { Textures, Exact };
const char* hydrostaticsMethodName(HydrostaticsMethod method);

/// One point of the righting-arm curve.
struct RightingArm {
    double heelDegrees = 0;
    double arm = 0;           ///< GZ, m: positive rights the body
    double trimDegrees = 0;   ///< the free trim at that heel
};

struct HydrostaticsResult {
    HydrostaticsMethod method = HydrostaticsMethod::Exact;
    double displacement = 0;        ///< displaced volume at equilibrium, m^3 (= mass / rho)
    double draft = 0;               ///< depth of the lowest point below the water, m
    double trimDegrees = 0;         ///< equilibrium rotation about z
    double heelDegrees = 0;         ///< equilibrium rotation about x
    double waterplaneArea = 0;      ///< m^2
    Eigen::Vector3d centerOfFlotation = Eigen::Vector3d::Zero();  ///< object space, m
    /// Heights above the keel (the lowest point), along the vertical at equilibrium, m.
    double kb = 0, kg = 0;
    double bmTransverse = 0, bmLongitudinal = 0;   ///< I_wp / V about x and about z, m
    double gmTransverse = 0, gmLongitudinal = 0;   ///< KB + BM - KG, water held as solid, m
    /// GM lost to the free surfaces, rho_t i / (rho V) summed, m; the effective GM is
    /// gm - loss.
    double freeSurfaceLossTransverse = 0, freeSurfaceLossLongitudinal = 0;
    std::vector<RightingArm> gz;    ///< 0 .. 180 degrees of heel, free trim
    /// First heel above the equilibrium where GZ turns from righting to capsizing: the
    /// equilibrium heel itself when no heel beyond it rights (negative GM, or neutral as a
    /// sphere), 180 when it rights all the way.
    double vanishingStabilityDegrees = 0;
};

/// Hydrostatics from the texel sums of the buoyancy evaluation (evaluateBuoyancyReference).
Result<HydrostaticsResult> hydrostaticsFromTextures(const SurfaceTextures& textures,
                                                    const HydrostaticBody& body,
                                                    const HydrostaticsSettings& settings);

/// Hydrostatics from the exact clip of the closed mesh (evaluateBuoyancyExact).
Result<HydrostaticsResult> hydrostaticsExact(const TriangleMesh& mesh, const HydrostaticBody& body,
                                             const HydrostaticsSettings& settings);

/// The free surfaces of the graph's partly filled nodes, the body upright: a box node's is
/// its horizontal section (the box scaled to its capacity, as the graph does), a sphere
/// node's the circle at its water level. `density` is the water's.
std::vector<FreeSurface> graphFreeSurfaces(const WaterGraph& graph, double density);

}  // namespace plimsoll
