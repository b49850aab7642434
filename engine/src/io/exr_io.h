// Internal OpenEXR adapter: float32 images with named channels, lossless (ZIP). The only
// place that includes OpenEXR.
#pragma once

#include "plimsoll/core/result.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace plimsoll::detail {

/// A float32 image, channels interleaved per pixel, row 0 at the top (EXR's order).
struct FloatImage {
    int width = 0;
    int height = 0;
    std::vector<std::string> channels;  ///< e.g. {"R", "G", "B", "A"}
    std::vector<float> pixels;          ///< width * height * channels.size()
    /// Per channel: stored as HALF (16-bit float) rather than float32; empty = all float32.
    /// Reading converts back to float32 either way (OpenEXR does).
    std::vector<bool> half;
};

/// A single-channel 32-bit unsigned integer image (ids, not values: EXR's UINT pixel type, so
/// no float rounding), row 0 at the top.
struct UintImage {
    int width = 0;
    int height = 0;
    std::string channel;                ///< e.g. "node"
    std::vector<std::uint32_t> pixels;  ///< width * height
};

/// A float32 image made a block of rows at a time, so that no whole image is held (a baked
/// 8192^2 texture's three images were 2.4 GB): fill(rows, first, count) writes rows
/// [first, first + count) (row 0 at the top), channels interleaved, into `rows`, which holds
/// count * width * channels.size() zeros.
struct FloatRows {
    int width = 0;
    int height = 0;
    std::vector<std::string> channels;
    std::function<void(float* rows, int first, int count)> fill;
    /// Per channel: stored as HALF, as FloatImage::half.
    std::vector<bool> half;
};

/// Writes atomically (temporary file + rename).
Status writeExr(const std::filesystem::path& path, const FloatImage& image);
/// Writes `file` as it is (the caller made it a temporary: replaceFilesTogether); errors name
/// `target`, the file the user knows.
Status writeExrFile(const std::filesystem::path& file, const FloatImage& image,
                    const std::filesystem::path& target);

Status writeExrFile(const std::filesystem::path& file, const FloatRows& image,
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
