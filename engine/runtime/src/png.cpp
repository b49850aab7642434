#include "png.hpp"

#include <zlib.h>

#include <cstdint>
#include <cstdlib>

namespace plimsoll_runtime {

namespace {

std::uint32_t be32(const std::string& s, std::size_t at) {
    return (std::uint32_t(static_cast<unsigned char>(s[at])) << 24) |
           (std::uint32_t(static_cast<unsigned char>(s[at + 1])) << 16) |
           (std::uint32_t(static_cast<unsigned char>(s[at + 2])) << 8) |
           std::uint32_t(static_cast<unsigned char>(s[at + 3]));
}

int paeth(int a, int b, int c) {
    const int p = a + b - c;
    const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    if (pa <= pb && pa <= pc) return a;
    return pb <= pc ? b : c;
}

}  // namespace

bool decodePng(const std::string& bytes, GreyImage& out, std::string& error) {
    static const char kSignature[] = "\x89PNG\r\n\x1a\n";
    if (bytes.size() < 8 || bytes.compare(0, 8, kSignature, 8) != 0) {
        error = "not a PNG file";
        return false;
    }
    std::size_t at = 8;
    std::uint32_t width = 0, height = 0;
    int depth = 0, colour = -1, interlace = 0;
    std::string idat;
    bool sawEnd = false;
    while (at + 12 <= bytes.size()) {
        const std::uint32_t length = be32(bytes, at);
        const std::string type = bytes.substr(at + 4, 4);
        if (length > bytes.size() - at - 12) {
            error = "PNG chunk " + type + " runs past the end of the file (truncated)";
            return false;
        }
        const std::size_t data = at + 8;
        const std::uint32_t crc = be32(bytes, data + length);
        const auto computed = static_cast<std::uint32_t>(
            crc32(0, reinterpret_cast<const Bytef*>(bytes.data() + at + 4), length + 4));
        if (crc != computed) {
            error = "PNG chunk " + type + " fails its CRC (corrupt)";
            return false;
        }
        if (type == "IHDR" && length >= 13) {
            width = be32(bytes, data);
            height = be32(bytes, data + 4);
            depth = static_cast<unsigned char>(bytes[data + 8]);
            colour = static_cast<unsigned char>(bytes[data + 9]);
            interlace = static_cast<unsigned char>(bytes[data + 12]);
        } else if (type == "IDAT") {
            idat.append(bytes, data, length);
        } else if (type == "IEND") {
            sawEnd = true;
            break;
        }
        at = data + length + 4;
    }
    if (!sawEnd) {
        error = "PNG has no IEND chunk (truncated)";
        return false;
    }
    int channels = 0;
    switch (colour) {
        case 0: channels = 1; break;
        case 2: channels = 3; break;
        case 4: channels = 2; break;
        case 6: channels = 4; break;
        default:
            error = "PNG colour type " + std::to_string(colour) + " is not supported (grey, "
                    "grey+alpha, RGB or RGBA)";
            return false;
    }
    if ((depth != 8 && depth != 16) || interlace != 0 || width == 0 || height == 0 ||
        width > 32768 || height > 32768) {
        error = "PNG must be non-interlaced, 8 or 16 bits, at most 32768 x 32768";
        return false;
    }
    const std::size_t bpp = static_cast<std::size_t>(channels) * (depth / 8);
    const std::size_t stride = bpp * width;
    std::vector<unsigned char> raw((stride + 1) * height);
    uLongf rawSize = static_cast<uLongf>(raw.size());
    const int z = uncompress(raw.data(), &rawSize, reinterpret_cast<const Bytef*>(idat.data()),
                             static_cast<uLong>(idat.size()));
    if (z != Z_OK || rawSize != raw.size()) {
        error = "PNG image data does not inflate to " + std::to_string(raw.size()) + " bytes";
        return false;
    }
    std::vector<unsigned char> previous(stride, 0), row(stride);
    out.width = static_cast<int>(width);
    out.height = static_cast<int>(height);
    out.values.resize(static_cast<std::size_t>(width) * height);
    for (std::uint32_t y = 0; y < height; ++y) {
        const unsigned char* line = raw.data() + y * (stride + 1);
        const int filter = line[0];
        for (std::size_t i = 0; i < stride; ++i) {
            const int x = line[1 + i];
            const int a = i >= bpp ? row[i - bpp] : 0;
            const int b = previous[i];
            const int c = i >= bpp ? previous[i - bpp] : 0;
            int v = 0;
            switch (filter) {
                case 0: v = x; break;
                case 1: v = x + a; break;
                case 2: v = x + b; break;
                case 3: v = x + (a + b) / 2; break;
                case 4: v = x + paeth(a, b, c); break;
                default:
                    error = "PNG row " + std::to_string(y) + " has an unknown filter " +
                            std::to_string(filter);
                    return false;
            }
            row[i] = static_cast<unsigned char>(v & 0xFF);
        }
        for (std::uint32_t x = 0; x < width; ++x) {
            const unsigned char* p = row.data() + x * bpp;
            // 8-bit values widen to 16 bits as v * 257 (stb's stbi_load_16 does the same).
            const unsigned v16 = depth == 16 ? (unsigned(p[0]) << 8) | p[1] : unsigned(p[0]) * 257u;
            out.values[static_cast<std::size_t>(y) * width + x] = static_cast<float>(v16) / 65535.0f;
        }
        previous.swap(row);
    }
    return true;
}

}  // namespace plimsoll_runtime
