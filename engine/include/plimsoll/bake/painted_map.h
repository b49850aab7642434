// Painted maps (permeability, surface density, thickness): greyscale images over the mesh's own
// UV layout, stored at their own resolution (independent of the physics texture size) as 8- or
// 16-bit PNG. Values are normalised to 0..1; what 1 means (kg/m^2, m, ...) is the caller's scale.
#pragma once

#include "plimsoll/core/result.h"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace plimsoll {

struct SurfaceTextures;

struct PaintedMap {
    int width = 0;
    int height = 0;
    /// Row-major, row 0 at the top of the image (v = 1), values 0..1.
    std::vector<float> values;

    /// Bilinear sample at mesh uv (u right, v up), clamped at the edges.
    double sample(double u, double v) const;
};

/// Loads a PNG (grey or colour: the first channel is used), 8 or 16 bits per channel: a regular
/// file of at most kMaxDataFileBytes, decoded by decodePaintedMap.
Result<PaintedMap> loadPaintedMap(const std::filesystem::path& path);

/// Decodes a PNG file image; `source` names it in errors. The size its header declares is
/// checked against kMaxPaintedMapSide before any pixel is decoded (a small file can declare an
/// image of gigabytes).
Result<PaintedMap> decodePaintedMap(std::string_view png, const std::string& source);

/// The map as a 16-bit greyscale PNG file image (values clamped to 0..1, rounded to 1/65535):
/// loadPaintedMap of it gives back the same values after the same rounding.
std::string encodePaintedMapPng16(const PaintedMap& map);

/// Writes encodePaintedMapPng16 atomically (file_util.h).
Status savePaintedMap(const PaintedMap& map, const std::filesystem::path& path);

/// The map's value times `scale` at every entry of the textures (its texel centre, taken back
/// to mesh uv through the bake's placement): e.g. surface density per entry for
/// textureShellMassProperties.
std::vector<double> sampleAtTexels(const PaintedMap& map, const SurfaceTextures& textures,
                                   double scale);

}  // namespace plimsoll
