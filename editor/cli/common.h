// Shared plumbing of the headless sub-commands: loading and checking a mesh with the messages
// a user needs, and progress on stderr.
#pragma once

#include "plimsoll/surface/atlas.h"
#include "plimsoll/bake/bake.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/geometry/validate.h"
#include "plimsoll/project/project.h"

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace plimsoll::cli {

/// Loads and validates for the exact integrals, which need a closed solid and ignore UVs;
/// prints the problems to stderr. Returns the mesh only when it is a closed solid.
std::optional<TriangleMesh> loadClosedMesh(const std::string& path);

/// The index of the body named `name` in `project` (empty name: the first body); prints what is
/// wrong to stderr (no such body, listing the names; no bodies) and returns nothing.
std::optional<std::size_t> bodyIndexByName(const Project& project, const std::string& name,
                                           const std::string& projectPath);

/// [x, y, z] for JSON output.
nlohmann::json vectorJson(const Eigen::Vector3d& v);

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
    double maxTexelStretch = BakeSettings{}.maxTexelStretch;
    AtlasMode atlas = AtlasMode::Auto;
};

/// Adds --size, --max-texel-stretch and --atlas to a sub-command; returns the --size option.
CLI::Option* addBakeOptions(CLI::App& command, BakeOptions& options);

/// A mesh ready to bake: loaded, validated (every non-UV error refuses it), with the UVs that
/// --atlas chooses; says on stderr when a generated atlas replaces the mesh's UVs.
struct BakeableMesh {
    TriangleMesh mesh;  ///< with the UVs to bake
    bool generatedAtlas = false;
};
std::optional<BakeableMesh> loadMeshForBake(const std::string& path, const BakeOptions& options);

/// Bakes with progress; prints the error and returns nothing on failure.
std::optional<SurfaceTextures> bakeWithProgress(const TriangleMesh& mesh,
                                                const BakeOptions& options);

}  // namespace plimsoll::cli
