// Shared plumbing of the headless sub-commands: loading and checking a mesh with the messages
// a user needs, and progress on stderr.
#pragma once

#include "plimsoll/bake.h"
#include "plimsoll/mesh.h"
#include "plimsoll/validate.h"

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace plimsoll::cli {

enum class MeshUse {
    Texture,  ///< the mesh's UVs will be baked: every validation error refuses it
    Exact,    ///< only the closed surface matters: UV problems are not errors here
};

/// Loads and validates; prints warnings (and, on refusal, the errors) to stderr. Returns the
/// mesh only when it is fit for `use`.
std::optional<TriangleMesh> loadCheckedMesh(const std::string& path, MeshUse use);

/// [x, y, z] for JSON output.
nlohmann::json vectorJson(const Eigen::Vector3d& v);

/// Strict "x,y,z": three finite numbers, nothing else (no spaces, no trailing text).
std::optional<Eigen::Vector3d> parseVector(const std::string& text);

/// A vector option is one argument, X,Y,Z, split and checked here so that a malformed one is
/// refused at parse time with the option's name. Negative numbers work as --name=-1,2,-3.
CLI::Option* addVectorOption(CLI::App& command, const std::string& name, Eigen::Vector3d& target,
                             const std::string& description);

/// Progress of long work on stderr: a live percentage on a terminal, nothing in logs.
ProgressCallback stderrProgress(const std::string& label);

/// The bake's accuracy options, shared by every sub-command that bakes.
struct BakeOptions {
    int size = 512;
    double maxTexelStretch = BakeSettings{}.maxTexelStretch;
};

/// Adds --size and --max-texel-stretch to a sub-command; returns the --size option.
CLI::Option* addBakeOptions(CLI::App& command, BakeOptions& options);

/// Bakes with progress; prints the error and returns nothing on failure.
std::optional<SurfaceTextures> bakeWithProgress(const TriangleMesh& mesh,
                                                const BakeOptions& options);

}  // namespace plimsoll::cli
