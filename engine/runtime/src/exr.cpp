// The bundle's EXR images through tinyexr (Debian's libtinyexr-dev, header-only here, inflating
// with zlib), so that a game links no OpenEXR or Imath. Only what the exporter writes is read:
// single-part scanline images, uncompressed or ZIP (engine/src/io/exr_io.cpp); the other
// codecs, tiles, deep and multi-part files are refused before any pixel is decoded.
#define TINYEXR_IMPLEMENTATION
#define TINYEXR_USE_MINIZ 0
#define TINYEXR_USE_THREAD 0
#define TINYEXR_USE_OPENMP 0
#include <zlib.h>
#include <tinyexr.h>

#include "exr.hpp"

#include <cstring>
#include <memory>

namespace plimsoll_runtime {

namespace {

/// A parsed header, freed on every path.
struct Header {
    EXRHeader header;
    Header() { InitEXRHeader(&header); }
    ~Header() { FreeEXRHeader(&header); }
    Header(const Header&) = delete;
    Header& operator=(const Header&) = delete;
};

/// A decoded image, freed when it was decoded. A failed LoadEXRImageFromMemory frees the image
/// itself and leaves stale pointers behind; and tinyexr 1.0.1 sets the image's channel count
/// only on success, so that free misses the channel planes unless the count is set before the
/// call (load() does).
struct Image {
    EXRImage image;
    bool loaded = false;
    Image() { InitEXRImage(&image); }
    ~Image() {
        if (loaded) FreeEXRImage(&image);
    }
    Image(const Image&) = delete;
    Image& operator=(const Image&) = delete;
};

/// tinyexr's message, freed, after "cannot read EXR: ".
bool failed(const std::string& path, const char* message, std::string& error) {
    error = path + ": cannot read EXR: " + (message ? message : "malformed file");
    if (message) FreeEXRErrorMessage(message);
    return false;
}

/// Parses the header and checks what the bundle's images are: one scanline part, ZIP or no
/// compression, a data window at (0, 0) of at most `maxPixels` pixels and no more float data
/// than the compressed bytes can hold (ZIP shrinks at most ~1000:1, so a 1 KB file declaring
/// gigabytes is a bomb, refused).
bool parse(const std::string& path, const std::string& bytes, std::size_t channels,
           std::uint64_t maxPixels, Header& out, int& width, int& height, std::string& error) {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    EXRVersion version;
    if (ParseEXRVersionFromMemory(&version, data, bytes.size()) != TINYEXR_SUCCESS) {
        error = path + ": cannot read EXR: not an OpenEXR file";
        return false;
    }
    if (version.tiled || version.multipart || version.non_image) {
        error = path +
                ": EXR is tiled, deep or multi-part (a bundle's images are single-part scanline "
                "images)";
        return false;
    }
    const char* message = nullptr;
    if (ParseEXRHeaderFromMemory(&out.header, &version, data, bytes.size(), &message) !=
        TINYEXR_SUCCESS)
        return failed(path, message, error);
    const EXRHeader& h = out.header;
    if (h.compression_type != TINYEXR_COMPRESSIONTYPE_NONE &&
        h.compression_type != TINYEXR_COMPRESSIONTYPE_ZIP &&
        h.compression_type != TINYEXR_COMPRESSIONTYPE_ZIPS) {
        error = path + ": EXR compression " + std::to_string(h.compression_type) +
                " (a bundle's images are uncompressed or ZIP)";
        return false;
    }
    const long long w = static_cast<long long>(h.data_window.max_x) - h.data_window.min_x + 1;
    const long long hh = static_cast<long long>(h.data_window.max_y) - h.data_window.min_y + 1;
    if (h.data_window.min_x != 0 || h.data_window.min_y != 0 || w <= 0 || hh <= 0) {
        error = path + ": EXR data window does not start at (0, 0)";
        return false;
    }
    const double pixels = double(w) * double(hh);
    if (pixels > double(maxPixels) ||
        pixels * double(channels) * 4.0 > 1100.0 * double(bytes.size()) + 65536.0) {
        error = path + ": EXR declares " + std::to_string(w) + " x " + std::to_string(hh) +
                " pixels, more than the bundle needs or its " + std::to_string(bytes.size()) +
                " bytes can hold";
        return false;
    }
    for (int c = 0; c < h.num_channels; ++c) {
        if (h.channels[c].x_sampling != 1 || h.channels[c].y_sampling != 1) {
            error = path + ": EXR channel '" + h.channels[c].name + "' is subsampled";
            return false;
        }
    }
    width = static_cast<int>(w);
    height = static_cast<int>(hh);
    return true;
}

int findChannel(const EXRHeader& h, const std::string& name) {
    for (int c = 0; c < h.num_channels; ++c) {
        if (name == h.channels[c].name) return c;
    }
    return -1;
}

bool load(const std::string& path, const std::string& bytes, const Header& header, Image& image,
          int width, int height, std::string& error) {
    const char* message = nullptr;
    // What tinyexr's own free on a failed decode reads to find the planes it allocated.
    image.image.num_channels = header.header.num_channels;
    if (LoadEXRImageFromMemory(&image.image, &header.header,
                               reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(),
                               &message) != TINYEXR_SUCCESS)
        return failed(path, message, error);
    image.loaded = true;
    if (!image.image.images || image.image.width != width || image.image.height != height) {
        error = path + ": cannot read EXR: its pixels do not fill the data window";
        return false;
    }
    return true;
}

}  // namespace

bool readExrFloat(const std::string& path, const std::string& bytes,
                  const std::vector<std::string>& channels, const std::vector<bool>& half,
                  std::uint64_t maxPixels, int& width, int& height, std::vector<float>& pixels,
                  std::string& error) {
    Header header;
    const std::size_t n = channels.size();
    if (!parse(path, bytes, n, maxPixels, header, width, height, error)) return false;
    std::vector<int> index(n);
    for (std::size_t c = 0; c < n; ++c) {
        index[c] = findChannel(header.header, channels[c]);
        if (index[c] < 0) {
            error = path + ": EXR has no channel '" + channels[c] + "'";
            return false;
        }
        const bool wantHalf = c < half.size() && half[c];
        if (header.header.pixel_types[index[c]] !=
            (wantHalf ? TINYEXR_PIXELTYPE_HALF : TINYEXR_PIXELTYPE_FLOAT)) {
            error = path + ": EXR channel '" + channels[c] + "' is not " +
                    (wantHalf ? "half" : "float32");
            return false;
        }
    }
    // Half channels are widened to float as they are decoded; float channels stay as stored.
    for (int c = 0; c < header.header.num_channels; ++c) {
        if (header.header.pixel_types[c] == TINYEXR_PIXELTYPE_HALF)
            header.header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
    }
    Image image;
    if (!load(path, bytes, header, image, width, height, error)) return false;
    const std::size_t count = static_cast<std::size_t>(width) * height;
    pixels.assign(count * n, 0.0f);
    for (std::size_t c = 0; c < n; ++c) {
        const auto* plane = reinterpret_cast<const float*>(image.image.images[index[c]]);
        for (std::size_t i = 0; i < count; ++i) pixels[i * n + c] = plane[i];
    }
    return true;
}

bool readExrUint(const std::string& path, const std::string& bytes, const std::string& channelName,
                 std::uint64_t maxPixels, int& width, int& height,
                 std::vector<std::uint32_t>& pixels, std::string& error) {
    Header header;
    if (!parse(path, bytes, 1, maxPixels, header, width, height, error)) return false;
    const int c = findChannel(header.header, channelName);
    if (c < 0 || header.header.pixel_types[c] != TINYEXR_PIXELTYPE_UINT) {
        error = path + ": EXR has no UINT channel '" + channelName + "'";
        return false;
    }
    Image image;
    if (!load(path, bytes, header, image, width, height, error)) return false;
    const std::size_t count = static_cast<std::size_t>(width) * height;
    pixels.resize(count);
    std::memcpy(pixels.data(), image.image.images[c], count * sizeof(std::uint32_t));
    return true;
}

}  // namespace plimsoll_runtime
