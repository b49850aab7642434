// What a scene's bodies, medium and simulation are made of, as a project describes them
// (project/project.h reads and writes them as `*.plim.json`; the editor edits them): plain
// values and paths, no file is read here.
#pragma once

#include "plimsoll/graph/graph.h"
#include "plimsoll/surface/atlas.h"
#include "plimsoll/physics/rigid_body.h"
#include "plimsoll/physics/water.h"
#include "plimsoll_eval/sleep.hpp"

#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plimsoll {

/// How a body's mass is spread. Both parts are optional and add up.
struct MaterialDesc {
    /// Solid of uniform density filling the mesh, kg/m^3.
    std::optional<double> density;
    /// Thin shell on the surface: surface density in kg/m^2 ("surface_density"), or
    /// thickness (m) times material density (kg/m^3) ("thickness", "material_density").
    std::optional<double> shellSurfaceDensity;
    /// Painted surface-density map (8/16-bit PNG over the mesh's UVs): white is
    /// shellSurfaceDensity, black 0. Empty: uniform.
    std::string shellDensityMap;
    /// Painted relative shell thickness ("thickness_map", needs a shell): scales the shell's
    /// surface density like shellDensityMap (both multiply). Empty: uniform.
    std::string shellThicknessMap;

    bool operator==(const MaterialDesc&) const = default;
};

/// The water graph of a hollow or permeable body (graph.h; "water_graph" in a body). A body
/// without one is sealed: no graph is computed for it.
struct WaterGraphDesc {
    std::string graph;  ///< graph.json ("graph"), required
    /// Scale of the body's permeability_map ("permeability", 0..1): white is this value.
    double permeability = 1.0;
    /// The graph's models: "inflow", "inflow_rate", "discharge_coefficient", "flow",
    /// "diffusion_pressure", "free_surface" and "seed". The water inside (density, viscosity,
    /// gravity) is not the body's to give: the World takes it from the scene's medium.
    GraphSettings settings;

    bool operator==(const WaterGraphDesc&) const = default;
};

/// Wave radiation of a body ("radiation" in a body; scene/scene_radiation.h computes it,
/// physics/cummins.h steps it): added mass and radiation damping computed at load time (or
/// read from the project's cache) from its wetted surface at rest, integrated with Cummins'
/// equation, and exported in the body's bundle for the runtime (docs/bundle.md "Radiation").
/// On by default: a project's rigid body that floats gets it without asking (BodyDesc::radiation
/// absent); `"radiation": false` or `{"enabled": false}` turns it off (the body then runs as
/// before radiation existed, with the old linear_damping stand-in).
struct RadiationDesc {
    bool enabled = true;  ///< "enabled": false keeps the settings but runs without
    /// "panel_edge": longest panel edge of the wetted surface, m (0: the cube root of the rest
    /// displacement over 2, resolvedRadiationDesc).
    double panelEdge = 0;
    int frequencies = 16;  ///< "frequencies": samples of A(omega), B(omega)
    /// "min_frequency", "max_frequency": rad/s (0: K L from 0.05 to 5, L half the cube root of
    /// the rest displacement).
    double minFrequency = 0;
    double maxFrequency = 0;

    bool operator==(const RadiationDesc&) const = default;
};

/// A body's level ladder ("lod" in a body; docs/design.md "Level of detail"): the mesh baked
/// again at coarser texture sizes, each a true bake, among which the World picks one per frame
/// for the buoyancy (World::setLevelPolicy). The mass properties stay those of texture_size.
/// A body without it has one level, texture_size. A deforming body or one with a water graph
/// keeps its own level (no ladder is made; the log says so).
struct LodDesc {
    /// Texture sizes of the levels ("levels"), texels per side, each in
    /// kMinTextureSize..texture_size; texture_size is always the finest level (added if absent).
    std::vector<int> levels;

    bool operator==(const LodDesc&) const = default;
};

/// What becomes of the openings of an open hull or container ("openings"; physics_solid.h).
enum class OpeningsMode {
    /// "open": closed by caps that let water in: the space behind them is a compartment of the
    /// body's water graph, empty at the start, that floods when the rim goes under.
    Open,
    /// "sealed": closed by caps that let no water in (a decked hull).
    Sealed,
    /// "none": left open: the body is its surface, and water stands wherever it reaches.
    None,
};
const char* openingsModeName(OpeningsMode mode);  ///< "open", "sealed", "none"
std::optional<OpeningsMode> parseOpeningsMode(std::string_view name);

/// The stand-in damping of a body without radiation (1/s), when the project gives none.
inline constexpr double kStandInDamping = 0.5;
/// The stand-in damping of a radiating body's vertical motion (1/s), when the project gives
/// none (docs/radiation.md "Default stand-in damping"): radiation damps heave, which has a
/// restoring force and so a frequency at which it makes waves.
inline constexpr double kRadiatingVerticalDamping = 0.05;
/// Its horizontal motion keeps kStandInDamping: a drift has no restoring force, and the
/// radiation damping of surge and sway vanishes as the frequency goes to zero, so radiation
/// leaves a drift undamped (a capsized cube drifted for a minute with 0.05).
inline constexpr double kRadiatingHorizontalDamping = kStandInDamping;
/// Its rotation keeps kStandInDamping too: a round body's rotation makes no waves at all (the
/// faceted uniform sphere of neutral_ball settled in 29.3 s with 0.5, and not within 30 s with
/// 0.1), nor does any body's yaw at zero frequency.
inline constexpr double kRadiatingAngularDamping = kStandInDamping;

/// One opening's cap ("caps" in a body, one entry per opening in the openings' order:
/// physics_solid.h, PhysicsSolid::openings). Unset members take the body's defaults.
struct CapDesc {
    /// "mode": "open" or "sealed" (not "none": a cap is there or the body has none); unset: the
    /// body's `openings` mode.
    std::optional<OpeningsMode> mode;
    /// "height": object-space y of the cap's plane, m (after `unit`); unset: just under the
    /// lowest point of the rim. A height above the rim, or at or below the bottom of the space
    /// behind the cap, is refused when the body is loaded (RepairSettings::capHeights).
    std::optional<double> height;

    bool operator==(const CapDesc&) const = default;
};

struct BodyDesc {
    std::string name;
    /// Mesh file (any format assimp reads). For a deforming body, the first frame.
    std::string mesh;
    /// Metres per unit of the mesh file ("unit": a name such as "cm" or a number); 0: the
    /// file's own unit (FBX UnitScaleFactor, glTF metres), metres for OBJ, STL and PLY.
    double unitScale = 0;
    /// A deforming body: further frames of the same mesh (same vertices and UVs, OBJ sequence),
    /// played at framesPerSecond and looped. Empty for a rigid body.
    std::vector<std::string> meshFrames;
    double framesPerSecond = 24.0;
    int textureSize = 256;  ///< physics texture, texels per side
    /// An accuracy budget instead of a size ("tolerance"): the largest force error allowed
    /// against the exact clip, a share of rho g V. The bake picks the smallest texture size
    /// that meets it (level_ladder.h, chooseLevelForTolerance) and textureSize becomes it.
    std::optional<double> tolerance;
    double maxTexelStretch = 4.0;  ///< sub-texel refinement (BakeSettings)
    /// Which UVs are baked ("atlas": "mesh", "auto" or "generate"). A generated atlas has the
    /// default AtlasSettings whatever textureSize is (so changing the physics texture size
    /// keeps the maps painted over it) and is cached beside the project (atlasCacheFile).
    AtlasMode atlas = AtlasMode::Auto;
    /// The openings of an open hull or container ("openings": "open", "sealed" or "none").
    OpeningsMode openings = OpeningsMode::Open;
    /// Per-cap settings ("caps"), by opening index; openings past its end take the defaults.
    /// Ignored with "openings": "none".
    std::vector<CapDesc> caps;
    /// Whether opening `index`'s cap lets water in (its mode, else the body's).
    OpeningsMode capMode(std::size_t index) const {
        if (openings == OpeningsMode::None) return OpeningsMode::None;
        return index < caps.size() && caps[index].mode ? *caps[index].mode : openings;
    }
    MaterialDesc material;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();         ///< R p + t: t, m
    Eigen::Vector3d rotationDegrees = Eigen::Vector3d::Zero();  ///< Rz Ry Rx, degrees
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();         ///< centre of mass, m/s
    Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();  ///< world, rad/s
    double dragCoefficient = 1.0;                               ///< C_d
    double frictionCoefficient = 0.0;                           ///< C_f (0: no skin friction)
    /// Hydrodynamic damping standing in for wave radiation, which the pressure and drag terms
    /// do not model: -m lambda v and -lambda I w, scaled by the submerged share of the volume
    /// (1/s). Quadratic drag alone lets small bobbing die out only as 1/t; 0 turns it off.
    /// Absent ("linear_damping", "angular_damping" not given): standInLinearDamping's,
    /// standInVerticalDamping's and standInAngularDamping's defaults, which depend on whether
    /// the body radiates. Given, linearDamping acts on the vertical motion as on the horizontal.
    std::optional<double> linearDamping;
    std::optional<double> angularDamping;
    /// Painted permeability map ("permeability_map", PNG over the mesh's UVs, 0..1: how much
    /// of the water in contact flows in, for the water graph). Empty: impermeable.
    std::string permeabilityMap;
    /// Water graph ("water_graph"); absent: a sealed body.
    std::optional<WaterGraphDesc> waterGraph;
    /// Wave radiation ("radiation"). Absent: on by default where it applies (a rigid body that
    /// floats: the scene loader computes it, and says so when it does not apply); present and
    /// enabled: asked for (a body it cannot apply to is refused); present and disabled: off.
    std::optional<RadiationDesc> radiation;
    /// Level ladder ("lod"); absent: one level, texture_size.
    std::optional<LodDesc> lod;
    /// Whether the body runs with radiation wherever it has been computed (absent or enabled).
    bool radiates() const { return !radiation || radiation->enabled; }
    /// Whether the project asks for radiation itself (present and enabled): it must then be
    /// computed, and a body it cannot apply to is an error rather than a note.
    bool radiationRequired() const { return radiation && radiation->enabled; }
    /// The stand-in damping the body runs with (1/s): linearDamping or angularDamping when given,
    /// else kStandInDamping without radiation (the value before radiation was on by default) and
    /// the kRadiating* values with it (docs/radiation.md "Default stand-in damping": radiation
    /// damps the heave about the rest waterline, so the stand-in keeps what radiation leaves
    /// undamped, a horizontal drift and the rotation). Linear: the horizontal momentum;
    /// vertical: the momentum along gravity.
    double standInLinearDamping(bool radiating) const;
    double standInVerticalDamping(bool radiating) const;
    double standInAngularDamping(bool radiating) const;

    bool deforms() const { return !meshFrames.empty(); }
    bool operator==(const BodyDesc&) const = default;
};

inline double BodyDesc::standInLinearDamping(bool radiating) const {
    return linearDamping.value_or(radiating ? kRadiatingHorizontalDamping : kStandInDamping);
}
inline double BodyDesc::standInVerticalDamping(bool radiating) const {
    return linearDamping.value_or(radiating ? kRadiatingVerticalDamping : kStandInDamping);
}
inline double BodyDesc::standInAngularDamping(bool radiating) const {
    return angularDamping.value_or(radiating ? kRadiatingAngularDamping : kStandInDamping);
}

/// The fluid the bodies are in (below the surface) — water, or air for a balloon.
struct MediumDesc {
    std::string name = "water";  ///< "water" or "air" (informative)
    double density = 1000.0;     ///< kg/m^3
    double viscosity = 1.0e-3;   ///< dynamic viscosity, Pa s

    bool operator==(const MediumDesc&) const = default;
};

struct SimulationDesc {
    Eigen::Vector3d gravity{0.0, -9.81, 0.0};  ///< m/s^2
    double timeStep = 1.0 / 60.0;              ///< s, one frame
    int subSteps = 4;                          ///< integration steps per frame (at least)
    /// More sub-steps are taken where a body's hydrostatic natural frequency omega (bounded
    /// from its bounding sphere) would make omega dt exceed this (rad). 0.5 keeps the
    /// symplectic step stable and its energy error within several percent; 0.025 keeps it
    /// within 1%, at 20 times the steps.
    double maxPhaseStep = 0.5;
    Integrator integrator = Integrator::SemiImplicitEuler;
    double duration = 10.0;  ///< s, for headless runs
    /// When a body at rest on calm water stops being computed (plimsoll_eval/sleep.hpp).
    plimsoll_eval::SleepSettings sleep;

    bool operator==(const SimulationDesc&) const = default;
};

}  // namespace plimsoll
