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

#include "plimsoll/bake.h"
#include "plimsoll/result.h"

#include <filesystem>
#include <string>

namespace plimsoll {

inline constexpr int kBakeSchemaVersion = 1;

/// Writes the three images and manifest.json into `folder` (created if missing). Each file is
/// written to a temporary name and renamed, so an earlier bake survives a failed one.
Status writeBakedTextures(const SurfaceTextures& textures, const std::filesystem::path& folder,
                          const std::string& sourceMesh);

/// Reads the sample list of a folder written by writeBakedTextures (float32 precision).
/// Checks the manifest's schema version and the samples' texels.
Result<SurfaceTextures> readBakedTextures(const std::filesystem::path& folder);

}  // namespace plimsoll
