// Internal OpenEXR adapter: float32 images with named channels, lossless (ZIP). The only
// place that includes OpenEXR.
#pragma once

#include "plimsoll/result.h"

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

/// Writes atomically (temporary file + rename).
Status writeExr(const std::filesystem::path& path, const FloatImage& image);
/// Writes `file` as it is (the caller made it a temporary: replaceFilesTogether); errors name
/// `target`, the file the user knows.
Status writeExrFile(const std::filesystem::path& file, const FloatImage& image,
                    const std::filesystem::path& target);

/// Reads the named channels (missing ones are an error naming the file and channel).
Result<FloatImage> readExr(const std::filesystem::path& path,
                           const std::vector<std::string>& channels);

}  // namespace plimsoll::detail
