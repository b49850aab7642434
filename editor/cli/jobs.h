// What the sub-commands compute, as functions that return their results and errors instead of
// printing them: the command line prints what they return, and the Python module (python/)
// returns the same facts to Python, so that both say the same thing about the same input. The
// JSON is what each command's --json prints.
#pragma once

#include "cli/common.h"

#include "plimsoll/export/bundle.h"
#include "plimsoll/geometry/validate.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/physics/hydrostatics.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/physics/rigid_body.h"
#include "plimsoll/physics/volume_check.h"
#include "plimsoll/project/project.h"
#include "plimsoll/repair/physics_solid.h"
#include "plimsoll/scene/scene_hydrostatics.h"
#include "plimsoll/scene/world.h"

#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plimsoll::cli {

// --- validate ------------------------------------------------------------------------------

/// How a mesh can be used, and why.
struct Verdict {
    const char* code = "as-is";  ///< "as-is", "generated-atlas", "physics-solid", "unusable"
    std::vector<std::string> reasons;
    std::optional<PhysicsSolid> solid;  ///< the solid used (the mesh itself when not repaired)
};

struct Validation {
    TriangleMesh mesh;
    ValidationReport report;
    MeshFileFacts facts;
    Verdict verdict;
    nlohmann::json json;  ///< what `validate --json` prints
};

/// Loads and judges a mesh. An error only where it cannot be read; an unusable mesh is a
/// Validation whose verdict says so.
Result<Validation> validateJob(const std::string& path, double unitScale);

// --- massprops -----------------------------------------------------------------------------

struct MassPropsJob {
    /// A mesh, or a project (*.plim.json): then body `body` of it (empty: the first) with its
    /// own material, painted maps, openings and texture size, as the World weighs it.
    std::string mesh;
    std::string body;
    BakeOptions bake;
    bool exact = false;
    double density = 1000.0;
    double shellDensity = 0.0;
    std::string shellDensityMap;
    bool densityGiven = false;  ///< --density given (with a shell: a solid too)
};

struct MassPropsOutcome {
    MassProperties props;
    MeshReport report;
    nlohmann::json json;  ///< what `massprops --json` prints
};

Result<MassPropsOutcome> massPropsJob(const MassPropsJob& job, const Reporter& reporter);

// --- buoyancy ------------------------------------------------------------------------------

struct BuoyancyJob {
    std::string mesh;
    BakeOptions bake;
    bool exact = false;
    std::string device;
    double waterLevel = 0.0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Vector3d rotationDegrees = Eigen::Vector3d::Zero();
    Motion motion;
    FluidSettings fluid;
    bool compareExact = false;
};

struct BuoyancyOutcome {
    BuoyancyResult result;
    std::string deviceName = "exact";
    double frameMs = 0;
    std::optional<SubmergedVolumeCheck> check;
    nlohmann::json json;  ///< what `buoyancy --json` prints
};

Result<BuoyancyOutcome> buoyancyJob(const BuoyancyJob& job, const Reporter& reporter);

// --- hydrostatics --------------------------------------------------------------------------

struct HydrostaticsJob {
    std::string project;
    std::string body;
    bool exact = false;
    double stepDegrees = 5.0;
};

/// One method's figures and how long they took.
struct MeasuredHydrostatics {
    HydrostaticsResult result;
    double seconds = 0;
};

struct HydrostaticsStudy {
    std::string label;  ///< the body as messages name it
    std::string bodyName;
    int textureSize = 0;
    bool exactOnly = false;
    double density = 0;  ///< of the water
    FloatingBody floating;
    std::vector<MeasuredHydrostatics>
        methods;                  ///< the textures' (unless exactOnly), the exact clip's
    nlohmann::json json() const;  ///< what `hydrostatics --json` prints
};

Result<HydrostaticsStudy> hydrostaticsJob(const HydrostaticsJob& job, const Reporter& reporter);

// --- simulate ------------------------------------------------------------------------------

struct SimulateJob {
    std::string project;  ///< a project file, or empty with `mesh` for a one-body scene
    std::optional<double> seconds;
    std::string device;
    std::optional<Integrator> integrator;
    // One-body scene from flags.
    std::string mesh;
    double unitScale = 0;
    double density = 500.0;
    int size = 128;
    double fluidDensity = 1000.0;
    double waterLevel = 0.0;
    bool noRadiation = false;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Vector3d rotationDegrees = Eigen::Vector3d::Zero();
};

/// A World ready to run and how many frames the job asks for.
struct PreparedSimulation {
    Project project;
    std::unique_ptr<World> world;
    long frames = 0;
};

Result<PreparedSimulation> prepareSimulation(const SimulateJob& job, const Reporter& reporter);

/// One frame, refused where it fails or a body leaves the finite numbers.
Status advanceFrameChecked(World& world);

/// The columns of `simulate --out`: time, body, then trajectoryRow's numbers.
inline constexpr const char* kTrajectoryHeader =
    "time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,submerged_volume,fx,fy,fz,mass,com_x,com_y,"
    "com_z";
/// A body's numbers after time and name: centre of mass (world), quaternion (w, x, y, z),
/// velocities, submerged volume, buoyant force, mass, centre of mass (object space).
std::array<double, 21> trajectoryRow(const SimulatedBody& body);

// --- export --------------------------------------------------------------------------------

struct ExportMode {
    bool check = false;    ///< write nothing; list what an export would change
    bool force = false;    ///< rewrite bundles made from unchanged inputs
    bool compact = false;  ///< half-float samples and images
};

/// A project's folder in the export folder: its file stem made a safe name, with "-2", "-3",
/// ... appended while an earlier project of the same export took it.
std::string exportFolderName(const std::string& fileStem, const std::vector<std::string>& taken);

/// Body `body` of `project` exported to (or, with check, compared with) `folder`.
Result<BundleReport> exportBody(const Project& project, std::size_t body,
                                const std::filesystem::path& folder, const ExportMode& mode,
                                const std::function<void(const std::string&)>& notice);

/// A bundle's figures in the export summary: texture size (and tolerance), texels, bytes, files.
nlohmann::json bundleReportJson(const BundleReport& report);

}  // namespace plimsoll::cli
