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
//
// The stability report designers read follows from these: tonnes per centimetre immersion,
// the moment to change trim one centimetre, KN cross curves, the largest GZ and its angle,
// the downflooding angle (the heel at which an opening of the body reaches the water) and
// the general criteria of the IMO 2008 Intact Stability Code (Res. MSC.267(85), Part A 2.2).
#pragma once

#include "plimsoll/core/result.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/physics/water.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace plimsoll {

struct SurfaceTextures;
struct WaterGraph;

/// A free surface inside the body: the water of a partly filled compartment, which moves to
/// the low side as the body heels and so lowers the effective GM by rho_t i / (rho V).
struct FreeSurface {
    double density = 1000.0;   ///< of the liquid in the compartment, kg/m^3
    double inertiaAboutX = 0;  ///< second moment of the surface about its own x axis, m^4
    double inertiaAboutZ = 0;  ///< about its own z axis, m^4
};

/// What floats: its mass and where it acts, the water it carries included.
struct HydrostaticBody {
    double mass = 0;                                         ///< kg, > 0
    Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();  ///< object space, m
    std::vector<FreeSurface> freeSurfaces;                   ///< partly filled compartments
    /// Where water gets in: object-space points of the body's openings (the permeable texels
    /// of its water graph, an open hull's caps among them), m. Empty: the body is sealed and
    /// has no downflooding angle.
    std::vector<Eigen::Vector3d> openings;
};

struct HydrostaticsSettings {
    double density = 1000.0;            ///< of the water the body floats in, kg/m^3
    double gravity = kStandardGravity;  ///< m/s^2 (enters only through the weight)
    double gzStepDegrees = 5.0;         ///< spacing of the GZ curve, 0 < step <= 90
    /// Heel and trim step of the exact clip's metacentric derivatives: Richardson's
    /// extrapolation over this step and twice it cancels the tan^2 term of the wall-sided
    /// curve.
    double derivativeStepDegrees = 1.0;
    /// Heel step of the curve the IS Code criteria integrate (Simpson's rule), degrees,
    /// 0 < step <= 5: on a wall-sided box the areas are within 2e-8 m rad of the closed form
    /// at 1 degree, 1e-5 at 5 degrees.
    double criteriaStepDegrees = 1.0;
    /// The KN cross curves: their heels (degrees, in (0, 180]) and displacements as multiples
    /// of the body's own (> 0; those the body cannot float are left out). Either empty: none.
    std::vector<double> crossCurveHeelsDegrees = {10, 20, 30, 40, 50, 60, 75, 90};
    std::vector<double> crossCurveDisplacementRatios = {0.5, 0.75, 1.0, 1.25, 1.5};
};

enum class HydrostaticsMethod { Textures, Exact };
const char* hydrostaticsMethodName(HydrostaticsMethod method);

/// One point of the righting-arm curve.
struct RightingArm {
    double heelDegrees = 0;
    double arm = 0;          ///< GZ, m: positive rights the body
    double trimDegrees = 0;  ///< the free trim at that heel
};

/// KN = GZ + KG sin(phi) against heel at one displacement: the righting arm about the keel
/// point K, which does not depend on the height of G.
struct CrossCurve {
    double displacement = 0;           ///< m^3
    std::vector<double> heelsDegrees;  ///< the settings' heels
    std::vector<double> kn;            ///< m, one per heel
};

/// One criterion of a stability code: the body's value against the required one.
struct StabilityCriterion {
    std::string name;  ///< "area_0_30", "area_0_40", "area_30_40", "gz_30", "angle_gz_max", "gm0"
    std::string unit;  ///< "m rad", "m" or "deg"
    double value = 0;
    double required = 0;  ///< the least value that passes
    bool pass = false;    ///< value >= required
};

/// The general intact stability criteria of the IMO 2008 IS Code (Res. MSC.267(85), Part A
/// 2.2.1-2.2.4), on the righting-arm curve corrected for free surfaces:
///   area under GZ from 0 to 30 degrees                          >= 0.055 m rad
///   area from 0 to 40 degrees, or to the downflooding angle      >= 0.090 m rad
///   area from 30 to 40 degrees, or to the downflooding angle     >= 0.030 m rad
///   largest GZ at 30 degrees or more                            >= 0.20 m
///   angle of the largest GZ                                     >= 25 degrees
///   initial metacentric height GM0                              >= 0.15 m
struct StabilityCriteria {
    bool pass = false;  ///< every criterion passes
    std::vector<StabilityCriterion> criteria;
};

struct HydrostaticsResult {
    HydrostaticsMethod method = HydrostaticsMethod::Exact;
    double displacement = 0;    ///< displaced volume at equilibrium, m^3 (= mass / rho)
    double draft = 0;           ///< depth of the lowest point below the water, m
    double trimDegrees = 0;     ///< equilibrium rotation about z
    double heelDegrees = 0;     ///< equilibrium rotation about x
    double waterplaneArea = 0;  ///< m^2
    Eigen::Vector3d centerOfFlotation = Eigen::Vector3d::Zero();  ///< object space, m
    /// Heights above the keel (the lowest point), along the vertical at equilibrium, m.
    double kb = 0, kg = 0;
    double bmTransverse = 0, bmLongitudinal = 0;  ///< I_wp / V about x and about z, m
    double gmTransverse = 0, gmLongitudinal = 0;  ///< KB + BM - KG, water held as solid, m
    /// GM lost to the free surfaces, rho_t i / (rho V) summed, m; the effective GM is
    /// gm - loss.
    double freeSurfaceLossTransverse = 0, freeSurfaceLossLongitudinal = 0;
    std::vector<RightingArm> gz;  ///< 0 .. 180 degrees of heel, free trim
    /// First heel above the equilibrium where GZ turns from righting to capsizing: the
    /// equilibrium heel itself when no heel beyond it rights (negative GM, or neutral as a
    /// sphere), 180 when it rights all the way.
    double vanishingStabilityDegrees = 0;

    // The stability report. Wherever G matters, the free surfaces count: GM0 is the effective
    // GM_T, and the curve the figures are read from is GZ - loss_T sin(phi) (G raised by the
    // loss; the same curve as `gz` without free surfaces).
    /// The waterline's length at equilibrium: the waterplane's extent along the body's length
    /// (world x, heeled and trimmed), m. The L of mct1cm.
    double waterlineLength = 0;
    double tonnesPerCentimetre = 0;  ///< TPC = rho A_wp / 10^5, t/cm
    /// MCT1cm = Delta GM_L,effective / (100 L), Delta = rho V / 1000 in tonnes, L the
    /// waterline's length: t m/cm.
    double momentToChangeTrim = 0;
    double gzMax = 0;         ///< the largest arm from 0 to 180 degrees, m
    double gzMaxDegrees = 0;  ///< its heel
    /// The least heel (from 0, the way `gz` heels) at which an opening reaches the water: 0
    /// when one is under water upright; none without openings, or when none reaches the
    /// water up to 180 degrees.
    std::optional<double> downfloodingDegrees;
    std::size_t openingCount = 0;         ///< the body's opening points
    std::vector<CrossCurve> crossCurves;  ///< by displacement, ascending
    StabilityCriteria isCode2008;
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
