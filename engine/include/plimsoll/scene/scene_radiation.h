// Wave radiation of a scene body (physics/radiation.h, physics/cummins.h) as the simulation
// uses it: the panel method on the body's wetted surface at rest, A(omega) and B(omega) over a
// frequency grid, the infinite-frequency added mass and the memory fit. Computed at load time
// (scene_loader.h caches it in the project's cache folder); nothing here reads or writes a
// file. docs/radiation.md says what is approximated.
#pragma once

#include "plimsoll/bake/bake.h"
#include "plimsoll/core/result.h"
#include "plimsoll/physics/cummins.h"
#include "plimsoll/physics/radiation.h"
#include "plimsoll/scene/scene_desc.h"
#include "plimsoll/scene/scene.h"

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll {

/// Bounds of RadiationDesc::frequencies.
inline constexpr int kMinRadiationFrequencies = 4;
inline constexpr int kMaxRadiationFrequencies = 200;
/// At most this many panels: the solver holds several N x N matrices (about 60 N^2 bytes) and
/// each frequency is an O(N^3) complex solve (2000 panels: 240 MB, seconds a frequency).
inline constexpr std::size_t kMaxRadiationPanels = 2000;

/// What the simulation and the `hydro` command need of a body's radiation. Object axes, the
/// body upright as its mesh is modelled (heel and trim zero), moments about its centre of mass.
struct BodyRadiation {
    double restVolume = 0;  ///< displaced at rest, m^3 (mass / density)
    double restHeight = 0;  ///< height of the object-space origin above the water at rest, m
    double panelEdge = 0;   ///< the longest panel edge asked for, m
    std::size_t panelCount = 0;
    std::vector<RadiationCoefficients> coefficients;  ///< increasing omega
    Matrix6d addedMassInfinity = Matrix6d::Zero();
    CumminsModel model;  ///< fitted to the above
};

/// The settings with their automatic values filled in for a body that displaces `restVolume`:
/// panel edge cbrt(V) / 2, frequencies from K L = 0.05 to 5 with L = cbrt(V) / 2.
RadiationDesc resolvedRadiationDesc(const RadiationDesc& desc, double restVolume, double gravity);

/// A hash of everything the coefficients depend on (the mesh's vertices and triangles, the
/// floating mass and centre, the resolved settings, density and gravity): the cache's key.
std::string radiationKey(const SceneBody& body, const RadiationDesc& desc, const MediumDesc& medium,
                         const Eigen::Vector3d& gravity);

/// The body's wetted surface at rest as the panel method takes it, the settings resolved.
struct RestRadiationSurface {
    double restVolume = 0;                  ///< m^3
    double restHeight = 0;                  ///< as BodyRadiation::restHeight
    RadiationDesc resolved;                 ///< resolvedRadiationDesc of the settings asked for
    std::optional<RadiationSolver> solver;  ///< always set on success
};

/// The solver for body's wetted surface at rest (its mass with its water graph's water, as
/// floatingBodyOf), `desc` resolved: the mesh raised until it displaces mass / density, clipped
/// at the surface, split to the panel edge. Refuses a body that does not float (denser than the
/// medium, or weightless), more panels than kMaxRadiationPanels (naming the count and the panel
/// edge), and zero gravity. `threads`: RadiationSettings::threads (0: all cores).
Result<RestRadiationSurface> restRadiationSurface(const SceneBody& body, const RadiationDesc& desc,
                                                  const MediumDesc& medium,
                                                  const Eigen::Vector3d& gravity,
                                                  unsigned threads = 0);

/// Why radiation by default (a body without "radiation") does not apply to `body`, or nothing
/// when it does: a deforming body (the panels are of one rigid mesh at rest), one that does
/// not float in `medium` (denser, or weightless), or a medium much lighter than water (air:
/// no free surface to make waves on). Cheap: no panel is solved.
std::optional<std::string> defaultRadiationInapplicable(const SceneBody& body,
                                                        const MediumDesc& medium);

/// The panel method on body's mesh at rest (restRadiationSurface, whose errors it gives) over
/// the resolved frequency grid (log-spaced), then A_inf and the memory fit. `progress` hears
/// 0..1 as the frequencies are solved; `threads` as restRadiationSurface's.
Result<BodyRadiation> computeBodyRadiation(const SceneBody& body, const RadiationDesc& desc,
                                           const MediumDesc& medium, const Eigen::Vector3d& gravity,
                                           const ProgressCallback& progress = {},
                                           unsigned threads = 0);

/// A rotational mode whose added inertia and damping over omega (A_inf, A(omega), B(omega) /
/// omega) all stay below this share of the largest translational A_inf times L^2 (L = cbrt of
/// the rest volume) is taken as one the body makes no waves in (docs/radiation.md).
inline constexpr double kNegligibleRotationalRadiation = 0.01;

/// The memory fit (cumminsModel) of stored coefficients, the other fields copied: what a cache
/// read ends with. Rotational modes below kNegligibleRotationalRadiation get no added inertia
/// and no memory.
void fitRadiationModel(BodyRadiation& radiation);

}  // namespace plimsoll
