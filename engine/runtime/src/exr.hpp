// The bundle's EXR images (samples.exr, texel_nodes.exr), read from bytes in memory.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace plimsoll_runtime {

/// Reads channels of an EXR file's bytes into one interleaved float buffer: channel c must be
/// stored as HALF where `half[c]`, else as float32 (`half` empty: all float32). At most
/// `maxPixels` pixels, and no more data than the file's bytes can hold, checked before the
/// pixels are allocated. `path` names the file in the error.
bool readExrFloat(const std::string& path, const std::string& bytes,
                  const std::vector<std::string>& channels, const std::vector<bool>& half,
                  std::uint64_t maxPixels, int& width, int& height, std::vector<float>& pixels,
                  std::string& error);

/// Reads one UINT channel, with the checks of readExrFloat.
bool readExrUint(const std::string& path, const std::string& bytes, const std::string& channelName,
                 std::uint64_t maxPixels, int& width, int& height,
                 std::vector<std::uint32_t>& pixels, std::string& error);

}  // namespace plimsoll_runtime
