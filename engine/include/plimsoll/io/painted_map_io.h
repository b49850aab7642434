// Painted maps as PNG files: 8- or 16-bit, grey or colour (the first channel) on reading,
// 16-bit greyscale on writing.
#pragma once

#include "plimsoll/surface/painted_map.h"
#include "plimsoll/core/result.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace plimsoll {

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

}  // namespace plimsoll
