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

/// A chunk type for messages: its four letters, or hex where a byte is not a letter (a cut or
/// corrupt "IEND" once printed as "IEN").
std::string chunkName(const std::string& type) {
    static const char kHex[] = "0123456789abcdef";
    bool letters = type.size() == 4;
    for (char c : type) letters = letters && ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'));
    if (letters) return type;
    std::string hex = "0x";
    for (char c : type) {
        hex += kHex[static_cast<unsigned char>(c) >> 4];
        hex += kHex[static_cast<unsigned char>(c) & 15];
    }
    return hex;
}

int paeth(int a, int b, int c) {
    const int p = a + b - c;
    const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    if (pa <= pb && pa <= pc) return a;
    return pb <= pc ? b : c;
}

/// What IHDR declares.
struct PngHeader {
    std::uint32_t width = 0, height = 0;
    int depth = 0, colour = -1, interlace = 0;
};

/// Walks the chunks from the signature to IEND: each inside the file with its CRC, IHDR first
/// and 13 bytes long; IHDR read into `header`, the IDAT chunks' data joined into `idat`.
bool readChunks(const std::string& bytes, PngHeader& header, std::string& idat,
                std::string& error) {
    static const char kSignature[] = "\x89PNG\r\n\x1a\n";
    if (bytes.size() < 8 || bytes.compare(0, 8, kSignature, 8) != 0) {
        error = "not a PNG file";
        return false;
    }
    std::size_t at = 8;
    while (at + 12 <= bytes.size()) {
        const std::uint32_t length = be32(bytes, at);
        const std::string type = chunkName(bytes.substr(at + 4, 4));
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
        if ((at == 8) != (type == "IHDR") || (type == "IHDR" && length != 13)) {
            error = "PNG does not start with its 13-byte IHDR chunk (found " + type + ")";
            return false;
        }
        if (type == "IHDR") {
            header.width = be32(bytes, data);
            header.height = be32(bytes, data + 4);
            header.depth = static_cast<unsigned char>(bytes[data + 8]);
            header.colour = static_cast<unsigned char>(bytes[data + 9]);
            header.interlace = static_cast<unsigned char>(bytes[data + 12]);
        } else if (type == "IDAT") {
            idat.append(bytes, data, length);
        } else if (type == "IEND") {
            return true;
        }
        at = data + length + 4;
    }
    error = "PNG has no IEND chunk (truncated)";
    return false;
}

/// Bytes per pixel of an image this reader takes (grey, grey+alpha, RGB or RGBA; 8 or 16 bits;
/// not interlaced; at most kMaxPngSide a side); 0, with `error`, for any other.
std::size_t bytesPerPixel(const PngHeader& h, std::string& error) {
    int channels = 0;
    switch (h.colour) {
        case 0:
            channels = 1;
            break;
        case 2:
            channels = 3;
            break;
        case 4:
            channels = 2;
            break;
        case 6:
            channels = 4;
            break;
        default:
            error = "PNG colour type " + std::to_string(h.colour) +
                    " is not supported (grey, grey+alpha, RGB or RGBA)";
            return 0;
    }
    if ((h.depth != 8 && h.depth != 16) || h.interlace != 0 || h.width == 0 || h.height == 0 ||
        h.width > kMaxPngSide || h.height > kMaxPngSide) {
        error = "PNG is " + std::to_string(h.width) + " x " + std::to_string(h.height) + ", " +
                std::to_string(h.depth) + " bits" + (h.interlace ? ", interlaced" : "") +
                ": it must be non-interlaced, 8 or 16 bits, at most " +
                std::to_string(kMaxPngSide) + " x " + std::to_string(kMaxPngSide);
        return 0;
    }
    return static_cast<std::size_t>(channels) * (h.depth / 8);
}

/// Row y's bytes from its filtered line (the filter type, then the bytes), `previous` the row
/// above (zeros for the first).
bool unfilterRow(const std::vector<unsigned char>& line, const std::vector<unsigned char>& previous,
                 std::size_t bpp, std::uint32_t y, std::vector<unsigned char>& row,
                 std::string& error) {
    const int filter = line[0];
    if (filter > 4) {
        error = "PNG row " + std::to_string(y) + " has an unknown filter " + std::to_string(filter);
        return false;
    }
    for (std::size_t i = 0; i < row.size(); ++i) {
        const int x = line[1 + i];
        const int a = i >= bpp ? row[i - bpp] : 0;
        const int b = previous[i];
        const int c = i >= bpp ? previous[i - bpp] : 0;
        int v = x;
        switch (filter) {
            case 1:
                v = x + a;
                break;
            case 2:
                v = x + b;
                break;
            case 3:
                v = x + (a + b) / 2;
                break;
            case 4:
                v = x + paeth(a, b, c);
                break;
            default:
                break;
        }
        row[i] = static_cast<unsigned char>(v & 0xFF);
    }
    return true;
}

}  // namespace

bool decodePng(const std::string& bytes, GreyImage& out, std::string& error) {
    PngHeader header;
    std::string idat;
    if (!readChunks(bytes, header, idat, error)) return false;
    const std::size_t bpp = bytesPerPixel(header, error);
    if (bpp == 0) return false;
    const std::uint32_t width = header.width, height = header.height;
    const std::size_t stride = bpp * width;
    // Deflate shrinks at most ~1032:1, so compressed data too short for the declared image is
    // refused before anything of the image's size is allocated (a 0.5 MB file declaring
    // gigabytes). Rows are inflated one at a time: no buffer of the whole raw image.
    const double rawBytes = double(stride + 1) * height;
    if (rawBytes > 1100.0 * double(idat.size()) + 1024.0) {
        error = "PNG declares " + std::to_string(width) + " x " + std::to_string(height) +
                " pixels, more than its " + std::to_string(idat.size()) +
                " bytes of image data can hold (corrupt or a decompression bomb)";
        return false;
    }
    z_stream z{};
    if (inflateInit(&z) != Z_OK) {
        error = "PNG: cannot start inflating";
        return false;
    }
    z.next_in = reinterpret_cast<Bytef*>(idat.data());
    z.avail_in = static_cast<uInt>(idat.size());
    std::vector<unsigned char> line(stride + 1), previous(stride, 0), row(stride);
    out.width = static_cast<int>(width);
    out.height = static_cast<int>(height);
    out.values.resize(static_cast<std::size_t>(width) * height);
    bool ok = true;
    for (std::uint32_t y = 0; y < height && ok; ++y) {
        z.next_out = line.data();
        z.avail_out = static_cast<uInt>(line.size());
        while (z.avail_out > 0) {
            const int status = inflate(&z, Z_NO_FLUSH);
            if (status == Z_OK || (status == Z_STREAM_END && z.avail_out == 0)) continue;
            error = "PNG image data ends or breaks at row " + std::to_string(y) + " of " +
                    std::to_string(height) + " (truncated or corrupt)";
            ok = false;
            break;
        }
        if (!ok || !(ok = unfilterRow(line, previous, bpp, y, row, error))) break;
        for (std::uint32_t x = 0; x < width; ++x) {
            const unsigned char* p = row.data() + x * bpp;
            // 8-bit values widen to 16 bits as v * 257 (stb's stbi_load_16 does the same).
            const unsigned v16 =
                header.depth == 16 ? (unsigned(p[0]) << 8) | p[1] : unsigned(p[0]) * 257u;
            out.values[static_cast<std::size_t>(y) * width + x] =
                static_cast<float>(v16) / 65535.0f;
        }
        previous.swap(row);
    }
    inflateEnd(&z);
    if (!ok) out.values.clear();
    return ok;
}

}  // namespace plimsoll_runtime
