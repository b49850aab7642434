// Baked textures on disk: a folder with float32 OpenEXR images (lossless) and manifest.json.
//   position.exr     RGBA: R,G,B = PT (object space, m), A = 1 where covered, 0 elsewhere
//   area_vector.exr  RGBA: R,G,B = AVT (m^2, outward), A = surface area in the texel (m^2)
//   coverage.exr     Y: share of the texel's UV square covered, 0..1
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

/// Reads a folder written by writeBakedTextures (float32 precision). Checks the manifest's
/// schema version and that the images match its texture size.
Result<SurfaceTextures> readBakedTextures(const std::filesystem::path& folder);

}  // namespace plimsoll
