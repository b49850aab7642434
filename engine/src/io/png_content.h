// Painted maps are PNG by content: the signature and every chunk are checked before a decoder
// runs, and the decoder is stb_image built for PNG alone (png_content.cpp), so a Radiance HDR,
// a progressive JPEG or any other format stb_image knows never reaches its reader, whatever the
// file is called.
#pragma once

#include "plimsoll/core/result.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace plimsoll {

/// What the bytes are, by their signature, for messages: "a PNG image", "a Radiance HDR image",
/// "a JPEG image", ... or "not an image format Plimsoll knows".
std::string imageTypeByContent(std::string_view bytes);

/// The PNG's structure, checked before decoding: the signature; chunks inside the file, each
/// with a valid type and CRC; IHDR first (width and height 1..maxSide, a valid bit depth and
/// colour type, deflate, no unknown filter or interlace method); one run of IDAT chunks holding
/// enough compressed bytes for the declared image (deflate shrinks at most ~1032:1); IEND last.
/// Anything not a PNG is refused naming its real type. `source` names the file in errors.
Status checkPngContent(std::string_view bytes, const std::string& source, int maxSide);

/// Decodes a PNG checked by checkPngContent to one 16-bit channel (grey, or the first channel's
/// luminance as stb_image gives it); an error names `source` and the decoder's reason.
struct Png16 {
    int width = 0, height = 0;
    std::basic_string<std::uint16_t> samples;
};
Result<Png16> decodePng16(std::string_view bytes, const std::string& source);

}  // namespace plimsoll
