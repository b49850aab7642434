#include "io/png_content.h"

#include <array>
#include <cstring>
#include <memory>

// stb_image limited to PNG, with its functions private to this file: the shared libstb (which
// also carries the deflate the PNG writer uses) decodes every format it knows, and HDR, JPEG
// and PIC inputs have hung it.
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wcast-qual"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wuseless-cast"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#include <stb_image.h>
#pragma GCC diagnostic pop

#include <zlib.h>

namespace plimsoll {

namespace {

/// PNG's chunk check: the CRC-32 of ISO 3309, zlib's.
std::uint32_t pngCrc(const unsigned char* data, std::size_t size) {
    return static_cast<std::uint32_t>(::crc32(0L, data, static_cast<uInt>(size)));
}

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

std::uint32_t bigEndian32(const unsigned char* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | p[3];
}

bool startsWith(std::string_view bytes, std::string_view prefix) {
    return bytes.size() >= prefix.size() && bytes.substr(0, prefix.size()) == prefix;
}

/// Bits per pixel of a valid (colour type, bit depth) pair; 0 for an invalid one.
int bitsPerPixel(int colourType, int depth) {
    auto depthIn = [&](std::initializer_list<int> allowed) {
        for (int d : allowed)
            if (d == depth) return true;
        return false;
    };
    switch (colourType) {
        case 0:
            return depthIn({1, 2, 4, 8, 16}) ? depth : 0;  // grey
        case 2:
            return depthIn({8, 16}) ? 3 * depth : 0;  // RGB
        case 3:
            return depthIn({1, 2, 4, 8}) ? depth : 0;  // palette
        case 4:
            return depthIn({8, 16}) ? 2 * depth : 0;  // grey and alpha
        case 6:
            return depthIn({8, 16}) ? 4 * depth : 0;  // RGBA
        default:
            return 0;
    }
}

}  // namespace

std::string imageTypeByContent(std::string_view b) {
    using namespace std::string_view_literals;
    if (startsWith(b, std::string_view(reinterpret_cast<const char*>(kPngSignature), 8)))
        return "a PNG image";
    if (startsWith(b, "#?RADIANCE"sv) || startsWith(b, "#?RGBE"sv)) return "a Radiance HDR image";
    if (startsWith(b, "\xFF\xD8\xFF"sv)) return "a JPEG image";
    if (startsWith(b, "GIF87a"sv) || startsWith(b, "GIF89a"sv)) return "a GIF image";
    if (startsWith(b, "8BPS"sv)) return "a Photoshop (PSD) image";
    if (startsWith(b, "\x53\x80\xF6\x34"sv)) return "a Softimage PIC image";
    if (startsWith(b, "\x76\x2F\x31\x01"sv)) return "an OpenEXR image";
    if (startsWith(b, "II*\0"sv) || startsWith(b, "MM\0*"sv)) return "a TIFF image";
    if (startsWith(b, "RIFF"sv) && b.size() >= 12 && b.substr(8, 4) == "WEBP"sv)
        return "a WebP image";
    if (startsWith(b, "qoif"sv)) return "a QOI image";
    if (startsWith(b, "BM"sv)) return "a BMP image";
    if (b.size() >= 3 && b[0] == 'P' && b[1] >= '1' && b[1] <= '7' &&
        (b[2] == '\n' || b[2] == ' ' || b[2] == '\r' || b[2] == '\t'))
        return "a PNM (PGM/PPM) image";
    return "not an image format Plimsoll knows (a TGA has no signature)";
}

Status checkPngContent(std::string_view bytes, const std::string& source, int maxSide) {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
    const std::size_t size = bytes.size();
    auto bad = [&](const std::string& why) {
        return makeError(ErrorKind::format, source + ": not a valid PNG: " + why);
    };
    if (size < 8 || std::memcmp(p, kPngSignature, 8) != 0)
        return makeError(ErrorKind::format, source + ": is " + imageTypeByContent(bytes) +
                                                ", not a PNG: painted maps are PNG files");
    std::size_t at = 8, chunks = 0;
    std::uint64_t idatBytes = 0, rawBytes = 0;
    bool sawIdat = false, idatEnded = false, sawEnd = false;
    while (at < size) {
        if (sawEnd) return bad("bytes after IEND");
        if (size - at < 12) return bad("a chunk is cut short at byte " + std::to_string(at));
        const std::uint32_t length = bigEndian32(p + at);
        if (length > 0x7FFFFFFFu || length > size - at - 12)
            return bad("chunk " + std::to_string(chunks) + " declares " + std::to_string(length) +
                       " bytes, past the end of the file");
        const unsigned char* type = p + at + 4;
        for (int i = 0; i < 4; ++i) {
            const bool letter =
                (type[i] >= 'A' && type[i] <= 'Z') || (type[i] >= 'a' && type[i] <= 'z');
            if (!letter) return bad("chunk " + std::to_string(chunks) + " has no valid type");
        }
        const std::string name(reinterpret_cast<const char*>(type), 4);
        if (pngCrc(type, length + 4) != bigEndian32(type + 4 + length))
            return bad("chunk " + name + " fails its CRC");
        const unsigned char* data = type + 4;
        if (chunks == 0) {
            if (name != "IHDR" || length != 13) return bad("the first chunk is not IHDR");
            const std::uint32_t w = bigEndian32(data), h = bigEndian32(data + 4);
            const int depth = data[8], colour = data[9];
            if (w == 0 || h == 0 || w > std::uint32_t(maxSide) || h > std::uint32_t(maxSide))
                return makeError(ErrorKind::limit,
                                 source + ": painted map declares " + std::to_string(w) + " x " +
                                     std::to_string(h) + " pixels, outside 1.." +
                                     std::to_string(maxSide) + " (kMaxPaintedMapSide, limits.h)");
            const int bits = bitsPerPixel(colour, depth);
            if (bits == 0)
                return bad("bit depth " + std::to_string(depth) + " with colour type " +
                           std::to_string(colour) + " is not PNG");
            if (data[10] != 0 || data[11] != 0 || data[12] > 1)
                return bad("unknown compression, filter or interlace method");
            rawBytes = std::uint64_t(h) * (1 + (std::uint64_t(w) * bits + 7) / 8);
        } else if (name == "IHDR") {
            return bad("a second IHDR");
        } else if (name == "IDAT") {
            if (idatEnded) return bad("IDAT chunks are not consecutive");
            sawIdat = true;
            idatBytes += length;
        } else {
            if (sawIdat) idatEnded = true;
            if (name == "IEND")
                sawEnd = true;
            else if ((type[0] & 0x20) == 0 && name != "PLTE")
                return bad("unknown critical chunk " + name);
        }
        at += 12 + std::size_t(length);
        ++chunks;
    }
    if (!sawEnd) return bad("no IEND chunk (truncated?)");
    if (!sawIdat) return bad("no IDAT chunk");
    if (idatBytes * 1032 + 1032 < rawBytes)
        return bad(std::to_string(idatBytes) + " compressed bytes cannot hold the declared image");
    return Ok{};
}

Result<Png16> decodePng16(std::string_view bytes, const std::string& source) {
    if (bytes.size() > 0x7FFFFFFFu)
        return makeError(ErrorKind::limit, source + ": larger than 2 GB");
    int width = 0, height = 0, channels = 0;
    std::unique_ptr<stbi_us, void (*)(void*)> pixels(
        stbi_load_16_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                 static_cast<int>(bytes.size()), &width, &height, &channels, 1),
        stbi_image_free);
    if (!pixels)
        return makeError(ErrorKind::format,
                         source + ": cannot read the PNG: " + stbi_failure_reason());
    Png16 png;
    png.width = width;
    png.height = height;
    png.samples.assign(pixels.get(), static_cast<std::size_t>(width) * height);
    return png;
}

}  // namespace plimsoll
