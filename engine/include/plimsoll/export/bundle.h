// Runtime bundles: what a game engine loads for one body of a project (docs/bundle.md).
// A bundle is a folder:
//   manifest.json    schema version, units, axes, texture, mass properties (exact and texture),
//                    material, atlas, water graph settings, and every other file with its
//                    SHA-256 and size
//   position.exr     RGBA float32: RGB = PT (object space, m), A = 1 where covered
//   area.exr         RGBA float32: RGB = AVT (m^2, outward), A = surface area (m^2)
//   coverage.exr     Y float32: covered share of each texel's UV square
//   samples.exr      the exact sample list the physics sums run over (bake_io.h)
//   *.png            the painted maps, 16-bit greyscale, over the baked UVs
//   graph.json       the water graph, when the body has one
//   texel_nodes.exr  UINT "node": 1 + graph.json index of the node each texel feeds, 0 where
//                    uncovered (with graph.json; schema 1.1)
// Exporting twice gives byte-identical files; a bundle is replaced atomically (a failed export
// leaves the previous one as it was). The manifest is a superset of a bake folder's, so
// readBakedTextures() reads a bundle's sample list.
#pragma once

#include "plimsoll_eval/format.hpp"

#include "plimsoll/project/project.h"
#include "plimsoll/core/result.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plimsoll {

/// Bundle schema: a reader accepts its own major version and any minor version (newer minors
/// only add optional fields and files); a new major may change or remove anything.
/// (The values live in the evaluation core, which the runtime library's reader also compiles.)
inline constexpr int kBundleSchemaMajor = plimsoll_eval::kBundleSchemaMajor;
inline constexpr int kBundleSchemaMinor = plimsoll_eval::kBundleSchemaMinor;

/// SHA-256 of `bytes` as 64 lowercase hex digits (OpenSSL's libcrypto).
std::string sha256Hex(std::string_view bytes);
/// SHA-256 of a file's content.
Result<std::string> sha256OfFile(const std::filesystem::path& path);

/// One file of a bundle as the manifest lists it.
struct BundleFile {
    std::string path;  ///< relative to the bundle folder
    std::string sha256;
    std::uintmax_t bytes = 0;
};

/// What writing or checking one body's bundle did.
struct BundleReport {
    std::string body;               ///< the body's name
    std::filesystem::path folder;   ///< the bundle folder
    std::vector<BundleFile> files;  ///< every file, manifest.json last
    std::size_t coveredTexels = 0;
    int textureSize = 0;
    /// Where the body gives a tolerance instead of a size: the tolerance and the measured
    /// force error of textureSize (level_ladder.h, LevelChoice).
    std::optional<double> tolerance;
    double forceError = 0;
    /// --check only: files whose content differs from what an export would write now, or that
    /// are missing or extra (relative paths, sorted). Empty: up to date.
    std::vector<std::string> outOfDate;
    /// unchangedBodyBundle only: the bundle on disk was kept, nothing was written.
    bool unchanged = false;
    std::uintmax_t totalBytes() const;
};

/// The folder name of body `index` in a project's export folder: its name with characters
/// other than [A-Za-z0-9._-] replaced by '_' ("body<index>" when empty), "-<index>" appended
/// when an earlier body of the project has the same folder name.
std::string bundleFolderName(const Project& project, std::size_t index);

/// How a bundle is written. `compact`: samples.exr and the images as half floats with a
/// per-body origin and scales (bake_io.h CompactSamples, docs/bundle.md "Compact bundles").
struct BundleOptions {
    bool compact = false;
};

/// Bakes body `index` of `project` (the same UVs and mass as World) and writes its bundle to
/// `folder`: built in a temporary folder beside it, then renamed over it. `log` gets notices
/// (an atlas generated, a deforming body exported at its first frame); may be empty.
Result<BundleReport> writeBodyBundle(const Project& project, std::size_t index,
                                     const std::filesystem::path& folder,
                                     const std::function<void(const std::string&)>& log = {},
                                     const BundleOptions& options = {});

/// SHA-256 over everything body `index`'s bundle is made from: the body's and the project's
/// settings (projectToJson of the project with only that body), the body's index and folder
/// name, the bytes of every source file (mesh, mesh frames, painted maps, water graph) and of
/// the project's atlas cache for the body when there is one, the bundle schema version and
/// plimsoll's version. The manifest records it as `input_sha256`.
/// An error names a source that cannot be read.
Result<std::string> bundleInputHash(const Project& project, std::size_t index,
                                    const BundleOptions& options = {});

/// The bundle in `folder` when exporting body `index` again would not change it: the folder
/// passes verifyBundle and its manifest's `input_sha256` equals bundleInputHash. Its report
/// (files as the manifest lists them, then manifest.json) has `unchanged` set. Nothing when
/// the bundle is missing, damaged, from another version or made from other inputs.
std::optional<BundleReport> unchangedBodyBundle(const Project& project, std::size_t index,
                                                const std::filesystem::path& folder,
                                                const BundleOptions& options = {});

/// Builds the bundle in a temporary folder and compares it file by file with `folder` (which
/// is not changed): BundleReport::outOfDate lists what differs.
Result<BundleReport> checkBodyBundle(const Project& project, std::size_t index,
                                     const std::filesystem::path& folder,
                                     const BundleOptions& options = {});

/// What verifyBundle found in a bundle folder.
struct BundleManifestInfo {
    int schemaMajor = 0;
    int schemaMinor = 0;
    std::string body;
    std::vector<BundleFile> files;  ///< as the manifest lists them
};

/// Reads `folder`/manifest.json and checks it as the runtime loader does, with the runtime's own
/// reader (plimsoll_runtime::readBundleManifest): the format name, a major version this reader
/// knows (kBundleSchemaMajor; any minor: newer minors only add), every path inside the bundle
/// and listed once, and every listed file present inside the folder (no link followed) with
/// its size and SHA-256. Errors name the file and what is wrong ("bundle schema 2.0 is newer
/// than this reader's 1.x", "area.exr: missing", "area.exr: SHA-256 ... does not match the
/// manifest's ...").
Result<BundleManifestInfo> verifyBundle(const std::filesystem::path& folder);

/// The manifest checks of verifyBundle that need no files (plimsoll_runtime::parseBundleManifest):
/// format, schema version, the file list, and every path inside the bundle. `source` names the
/// manifest in messages.
Result<BundleManifestInfo> parseBundleManifest(const std::string& text, const std::string& source);

}  // namespace plimsoll
