// Shared plumbing of the headless sub-commands: loading and checking a mesh with the messages
// a user needs, and progress on stderr.
#pragma once

#include "plimsoll/surface/atlas.h"
#include "plimsoll/bake/bake.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/geometry/validate.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/project/project.h"
#include "plimsoll/repair/physics_solid.h"

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>

namespace plimsoll::cli {

/// Where a job's notes and progress go: the command line prints them on stderr (progress only
/// on a terminal); the Python module hands the notes to its caller and shows no progress.
struct Reporter {
    /// Text as the command line prints it ("note: ...\n", a validation report); empty: dropped.
    std::function<void(const std::string&)> notes;
    /// A progress callback for a labelled piece of work; empty: no progress.
    std::function<ProgressCallback(const std::string&)> progress;

    void note(const std::string& text) const {
        if (notes) notes(text);
    }
    ProgressCallback progressFor(const std::string& label) const {
        return progress ? progress(label) : ProgressCallback{};
    }
};

/// Notes on stderr, progress on a terminal: the command line's reporter.
Reporter stderrReporter();

/// What loading a mesh found and did: the unit applied, the file's parts, and the physics
/// solid's repairs and volumes (no repairs: the mesh is used as it is).
struct MeshReport {
    MeshFileFacts facts;
    std::vector<Repair> repairs;
    double materialVolume = 0;      ///< m^3, exact, of the solid used
    double displacementVolume = 0;  ///< m^3, exact, of the sealed solid
    /// The space behind the caps of the solid's openings, at density 1 (no mass: none).
    MassProperties hollow;
    bool repaired() const { return !repairs.empty(); }
};

/// Adds --unit (metres per file unit, or m, cm, mm, in, ft, ...; default: the file's own unit,
/// metres for OBJ, STL and PLY).
CLI::Option* addUnitOption(CLI::App& command, double& unitScale);

/// Loads and validates for the exact integrals, which need a closed solid and ignore UVs; the
/// problems and repairs go to `reporter`, the error that stops it is returned.
Result<TriangleMesh> closedMeshOf(const std::string& path, double unitScale, MeshReport* report,
                                  const Reporter& reporter);

/// Loads and validates for the exact integrals, which need a closed solid and ignore UVs;
/// prints the problems to stderr. A surface that is not one closed solid as it is gives its
/// physics solid (physics_solid.h), and says so with the repairs; nothing when none can be
/// made.
std::optional<TriangleMesh> loadClosedMesh(const std::string& path, double unitScale = 0,
                                           MeshReport* report = nullptr);

/// "repairs": [{kind, count, volume_change, detail}] for JSON output.
nlohmann::json repairsJson(const std::vector<Repair>& repairs);

/// The index of the body named `name` in `project` (empty name: the first body); the error
/// says what is wrong (no such body, listing the names; no bodies). bodyIndexByName prints it
/// to stderr and returns nothing.
Result<std::size_t> bodyIndexOf(const Project& project, const std::string& name,
                                const std::string& projectPath);
std::optional<std::size_t> bodyIndexByName(const Project& project, const std::string& name,
                                           const std::string& projectPath);

/// [x, y, z] for JSON output.
nlohmann::json vectorJson(const Eigen::Vector3d& v);

/// A report as JSON text (dump(indent)), bytes that are not UTF-8 (a mesh's group name, a file
/// name) written as U+FFFD: nlohmann's dump() throws on them, which turned one error into two
/// and left the report unwritten.
std::string reportJson(const nlohmann::json& report, int indent = 2);

/// Strict "x,y,z": three finite numbers, nothing else (no spaces, no trailing text).
std::optional<Eigen::Vector3d> parseVector(const std::string& text);

/// A vector option is one argument, X,Y,Z, split and checked here so that a malformed one is
/// refused at parse time with the option's name. Negative numbers work as --name=-1,2,-3.
CLI::Option* addVectorOption(CLI::App& command, const std::string& name, Eigen::Vector3d& target,
                             const std::string& description);

/// Number checks for options. CLI11's PositiveNumber and NonNegativeNumber let "nan" through
/// (NaN <= 0 is false) and accept "inf"; these refuse both, at parse time, naming the option.
extern const CLI::Validator kFiniteNumber;
extern const CLI::Validator kFinitePositive;
extern const CLI::Validator kFiniteNonNegative;
/// A path option that is not empty: `--out ""` would write into the current folder.
extern const CLI::Validator kNonEmptyPath;

/// Progress of long work on stderr: a live percentage on a terminal, nothing in logs.
ProgressCallback stderrProgress(const std::string& label);

/// The bake's options, shared by every sub-command that bakes.
struct BakeOptions {
    int size = 512;
    double unitScale =
        0;  ///< metres per file unit (--unit, where the command has it); 0: the file's
    double maxTexelStretch = BakeSettings{}.maxTexelStretch;
    AtlasMode atlas = AtlasMode::Auto;
};

/// Adds --size, --max-texel-stretch and --atlas to a sub-command; returns the --size option.
CLI::Option* addBakeOptions(CLI::App& command, BakeOptions& options);

/// A mesh ready to bake: loaded in metres, validated, replaced by its physics solid when it is
/// not one closed solid (physics_solid.h; refused when none can be made), with the UVs that
/// --atlas chooses; says on stderr what was repaired and when a generated atlas replaces the
/// mesh's UVs.
struct BakeableMesh {
    TriangleMesh mesh;  ///< with the UVs to bake
    bool generatedAtlas = false;
    MeshReport report;
};
Result<BakeableMesh> bakeableMeshOf(const std::string& path, const BakeOptions& options,
                                    const Reporter& reporter);
std::optional<BakeableMesh> loadMeshForBake(const std::string& path, const BakeOptions& options);

/// Bakes with progress, its cost said first (bake_cost.h).
Result<SurfaceTextures> bakeTextures(const TriangleMesh& mesh, const BakeOptions& options,
                                     const Reporter& reporter);
/// Bakes with progress; prints the error and returns nothing on failure.
std::optional<SurfaceTextures> bakeWithProgress(const TriangleMesh& mesh,
                                                const BakeOptions& options);

/// `text` for an XML attribute or element (JUnit reports, SVG plots): the five markup
/// characters as entities, bytes that are not UTF-8 as U+FFFD, and control characters XML 1.0
/// does not admit as spaces.
std::string xmlEscaped(const std::string& text);

}  // namespace plimsoll::cli
