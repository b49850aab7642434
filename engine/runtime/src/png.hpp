// Minimal PNG reader for the bundle's painted maps: non-interlaced greyscale, grey+alpha, RGB
// or RGBA at 8 or 16 bits (the exporter writes 16-bit greyscale); the first channel is used,
// as the engine's loadPaintedMap does. Inflate is zlib's (OpenEXR's own dependency).
#pragma once

#include <string>
#include <vector>

namespace plimsoll_runtime {

/// Largest side read: the engine's kMaxPaintedMapSide (limits.h), which its exporter keeps to.
constexpr unsigned kMaxPngSide = 8192;

struct GreyImage {
    int width = 0, height = 0;
    std::vector<float> values;  ///< row 0 at the top (v = 1), 0..1 (v / 65535 or v / 255)
};

/// Decodes `bytes`; on failure returns false with `error` saying why (no file name).
bool decodePng(const std::string& bytes, GreyImage& out, std::string& error);

}  // namespace plimsoll_runtime
