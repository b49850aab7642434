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

#include "plimsoll/project.h"
#include "plimsoll/result.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace plimsoll {

/// Bundle schema: a reader accepts its own major version and any minor version (newer minors
/// only add optional fields and files); a new major may change or remove anything.
inline constexpr int kBundleSchemaMajor = 1;
inline constexpr int kBundleSchemaMinor = 1;

/// SHA-256 of `bytes` as 64 lowercase hex digits (OpenSSL's libcrypto).
std::string sha256Hex(std::string_view bytes);
/// SHA-256 of a file's content.
Result<std::string> sha256OfFile(const std::filesystem::path& path);

/// One file of a bundle as the manifest lists it.
struct BundleFile {
    std::string path;      ///< relative to the bundle folder
    std::string sha256;
    std::uintmax_t bytes = 0;
};

/// What writing or checking one body's bundle did.
struct BundleReport {
    std::string body;                    ///< the body's name
    std::filesystem::path folder;        ///< the bundle folder
    std::vector<BundleFile> files;       ///< every file, manifest.json last
    std::size_t coveredTexels = 0;
    int textureSize = 0;
    /// --check only: files whose content differs from what an export would write now, or that
    /// are missing or extra (relative paths, sorted). Empty: up to date.
    std::vector<std::string> outOfDate;
    std::uintmax_t totalBytes() const;
};

/// The folder name of body `index` in a project's export folder: its name with characters
/// other than [A-Za-z0-9._-] replaced by '_' ("body<index>" when empty), "-<index>" appended
/// when an earlier body of the project has the same folder name.
std::string bundleFolderName(const Project& project, std::size_t index);

/// Bakes body `index` of `project` (the same UVs and mass as World) and writes its bundle to
/// `folder`: built in a temporary folder beside it, then renamed over it. `log` gets notices
/// (an atlas generated, a deforming body exported at its first frame); may be empty.
Result<BundleReport> writeBodyBundle(const Project& project, std::size_t index,
                                     const std::filesystem::path& folder,
                                     const std::function<void(const std::string&)>& log = {});

/// Builds the bundle in a temporary folder and compares it file by file with `folder` (which
/// is not changed): BundleReport::outOfDate lists what differs.
Result<BundleReport> checkBodyBundle(const Project& project, std::size_t index,
                                     const std::filesystem::path& folder);

/// What verifyBundle found in a bundle folder.
struct BundleManifestInfo {
    int schemaMajor = 0;
    int schemaMinor = 0;
    std::string body;
    std::vector<BundleFile> files;       ///< as the manifest lists them
};

/// Reads `folder`/manifest.json and checks it the way a runtime loader must: the format name,
/// a major version this reader knows (kBundleSchemaMajor; any minor: newer minors only add),
/// and every listed file present with its size and SHA-256. Errors name the file and what is
/// wrong ("bundle schema 2.0 is newer than this reader's 1.x", "area.exr: missing",
/// "area.exr: SHA-256 ... does not match the manifest's ...").
Result<BundleManifestInfo> verifyBundle(const std::filesystem::path& folder);

/// The manifest checks of verifyBundle that need no files: format, schema version, the file
/// list, and every listed path inside the bundle. `source` names the manifest in messages.
Result<BundleManifestInfo> parseBundleManifest(const std::string& text, const std::string& source);

}  // namespace plimsoll
