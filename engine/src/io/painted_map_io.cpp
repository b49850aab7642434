#include "plimsoll/io/painted_map_io.h"

#include "plimsoll/core/limits.h"
#include "plimsoll/io/file_util.h"

#include "io/png_content.h"

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <memory>

// Debian's libstb exports stb_image_write's deflate; PNG's own chunking is done here because
// stbi_write_png writes 8 bits per channel only.
extern "C" unsigned char* stbi_zlib_compress(unsigned char* data, int dataLength, int* outLength,
                                             int quality);

#include <zlib.h>

namespace plimsoll {

namespace {

/// PNG's chunk check: the CRC-32 of ISO 3309, zlib's.
std::uint32_t pngCrc(const unsigned char* data, std::size_t size) {
    return static_cast<std::uint32_t>(::crc32(0L, data, static_cast<uInt>(size)));
}

void appendBigEndian(std::string& out, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out += static_cast<char>((v >> shift) & 0xFF);
}

void appendChunk(std::string& out, const char type[4], const std::string& data) {
    appendBigEndian(out, static_cast<std::uint32_t>(data.size()));
    const std::string typed = std::string(type, 4) + data;
    out += typed;
    appendBigEndian(out,
                    pngCrc(reinterpret_cast<const unsigned char*>(typed.data()), typed.size()));
}

}  // namespace

std::string encodePaintedMapPng16(const PaintedMap& map) {
    // Raw scanlines: filter byte 0 (none), then big-endian 16-bit samples.
    std::string raw;
    raw.reserve(static_cast<std::size_t>(map.height) * (1 + 2 * map.width));
    for (int y = 0; y < map.height; ++y) {
        raw += '\0';
        for (int x = 0; x < map.width; ++x) {
            const float v =
                std::clamp(map.values[static_cast<std::size_t>(y) * map.width + x], 0.0f, 1.0f);
            const auto q = static_cast<std::uint16_t>(std::lround(v * 65535.0f));
            raw += static_cast<char>(q >> 8);
            raw += static_cast<char>(q & 0xFF);
        }
    }
    int compressedLength = 0;
    unsigned char* compressed =
        stbi_zlib_compress(reinterpret_cast<unsigned char*>(raw.data()),
                           static_cast<int>(raw.size()), &compressedLength, 8);
    std::string png("\x89PNG\r\n\x1a\n", 8);
    std::string header;
    appendBigEndian(header, static_cast<std::uint32_t>(map.width));
    appendBigEndian(header, static_cast<std::uint32_t>(map.height));
    header += '\x10';                // bit depth 16
    header += '\0';                  // colour type 0: greyscale
    header += std::string(3, '\0');  // deflate, adaptive filtering, no interlace
    appendChunk(png, "IHDR", header);
    appendChunk(png, "IDAT", std::string(reinterpret_cast<char*>(compressed), compressedLength));
    std::free(compressed);
    appendChunk(png, "IEND", "");
    return png;
}

Status savePaintedMap(const PaintedMap& map, const std::filesystem::path& path) {
    if (map.width <= 0 || map.height <= 0 ||
        map.values.size() != static_cast<std::size_t>(map.width) * map.height) {
        return makeError(ErrorKind::format, path.string() + ": painted map has no pixels");
    }
    const std::string png = encodePaintedMapPng16(map);
    return writeFileAtomically(path, [&](std::ostream& out) {
        out.write(png.data(), static_cast<std::streamsize>(png.size()));
        return static_cast<bool>(out);
    });
}

Result<PaintedMap> loadPaintedMap(const std::filesystem::path& path) {
    Result<std::string> bytes = readWholeFile(path, kMaxDataFileBytes, "kMaxDataFileBytes");
    if (!bytes) return bytes.error();
    return decodePaintedMap(*bytes, path.string());
}

Result<PaintedMap> decodePaintedMap(std::string_view png, const std::string& source) {
    // PNG by content before any decoder runs; the decoder then knows PNG alone.
    if (Status checked = checkPngContent(png, source, kMaxPaintedMapSide); !checked.ok())
        return checked.error();
    Result<Png16> decoded = decodePng16(png, source);
    if (!decoded) return decoded.error();
    PaintedMap map;
    map.width = decoded->width;
    map.height = decoded->height;
    map.values.resize(decoded->samples.size());
    for (std::size_t i = 0; i < map.values.size(); ++i)
        map.values[i] = decoded->samples[i] / 65535.0f;
    return map;
}

}  // namespace plimsoll
