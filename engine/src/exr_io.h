// Internal OpenEXR adapter: float32 images with named channels, lossless (ZIP). The only
// place that includes OpenEXR.
#pragma once

#include "plimsoll/result.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace plimsoll::detail {

/// A float32 image, channels interleaved per pixel, row 0 at the top (EXR's order).
struct FloatImage {
    int width = 0;
    int height = 0;
    std::vector<std::string> channels;  ///< e.g. {"R", "G", "B", "A"}
    std::vector<float> pixels;          ///< width * height * channels.size()
};

/// A single-channel 32-bit unsigned integer image (ids, not values: EXR's UINT pixel type, so
/// no float rounding), row 0 at the top.
struct UintImage {
    int width = 0;
    int height = 0;
    std::string channel;                ///< e.g. "node"
    std::vector<std::uint32_t> pixels;  ///< width * height
};

/// Writes atomically (temporary file + rename).
Status writeExr(const std::filesystem::path& path, const FloatImage& image);
/// Writes `file` as it is (the caller made it a temporary: replaceFilesTogether); errors name
/// `target`, the file the user knows.
Status writeExrFile(const std::filesystem::path& file, const FloatImage& image,
                    const std::filesystem::path& target);

/// Writes a UINT image atomically, ZIP-compressed (lossless).
Status writeExr(const std::filesystem::path& path, const UintImage& image);

/// Reads the named channels (missing ones are an error naming the file and channel).
Result<FloatImage> readExr(const std::filesystem::path& path,
                           const std::vector<std::string>& channels);

}  // namespace plimsoll::detail

namespace plimsoll::detail {

/// Reads one UINT channel (an error naming the file when it is missing or not UINT).
Result<UintImage> readExrUint(const std::filesystem::path& path, const std::string& channel);

}  // namespace plimsoll::detail
