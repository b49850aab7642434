// Baked textures on disk: a folder with float32 OpenEXR images (lossless) and manifest.json.
//   position.exr     RGBA: R,G,B = PT (object space, m), A = 1 where covered, 0 elsewhere
//   area_vector.exr  RGBA: R,G,B = AVT (m^2, outward), A = surface area in the texel (m^2)
//   coverage.exr     Y: share of the texel's UV square covered, 0..1
//   samples.exr      the compact sample list itself (texel, point, area vector, area,
//                    coverage), rows of 1024 entries: what the physics sums run over
// The three images merge the entries of a texel (shared by two UV islands or refined where the
// map squeezes surface); they are for viewing and painting, the sample list is exact.
// Image row 0 is the top of the texture (v = 1), as UV editors and image viewers show it:
// texel (x, y) of SurfaceTextures is pixel (x, N - 1 - y).
#pragma once

#include "plimsoll/bake/bake.h"
#include "plimsoll/core/result.h"

#include <filesystem>
#include <string>

namespace plimsoll {

inline constexpr int kBakeSchemaVersion = 1;

/// Writes the three images and manifest.json into `folder` (created if missing). Each file is
/// written to a temporary name and renamed, so an earlier bake survives a failed one.
Status writeBakedTextures(const SurfaceTextures& textures, const std::filesystem::path& folder,
                          const std::string& sourceMesh);

/// The compact sample list of a bundle exported with --compact (docs/bundle.md "Compact
/// bundles"): every value stored as a 16-bit half float, points as (p - origin) / positionScale
/// and area vectors and areas as a / areaScale, so that all lie in [-1, 1] where a half keeps
/// 11 significant bits. The texel indices stay float32 (a half holds integers exactly only up
/// to 2048).
struct CompactSamples {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< the centre of the points' bounding box
    double positionScale = 1;                          ///< the largest |p - origin| component (m)
    double areaScale = 1;  ///< the largest area-vector component or area (m^2)
};
/// The encoding that fits `textures`' samples into [-1, 1].
CompactSamples compactSamplesFor(const SurfaceTextures& textures);
/// samples.exr's channels in the compact encoding: names differ from the float32 list's, so a
/// reader that does not know the encoding refuses the file instead of misreading it.
const std::vector<std::string>& compactSampleChannels();
/// As writeBakedTextures, with samples.exr in `compact`'s encoding and the three images stored
/// as half floats (same channels and meaning, about 3 significant digits).
Status writeCompactBakedTextures(const SurfaceTextures& textures,
                                 const std::filesystem::path& folder, const std::string& sourceMesh,
                                 const CompactSamples& compact);

/// Reads the sample list of a folder written by writeBakedTextures (float32 precision).
/// Checks the manifest's schema version and the samples' texels.
Result<SurfaceTextures> readBakedTextures(const std::filesystem::path& folder);

}  // namespace plimsoll
