#include "plimsoll/io/json_depth.h"

namespace plimsoll {

Status checkJsonDepth(std::string_view text, const std::string& source, std::uint64_t maxDepth) {
    std::uint64_t depth = 0;
    bool inString = false, escaped = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (escaped)
                escaped = false;
            else if (c == '\\')
                escaped = true;
            else if (c == '"')
                inString = false;
            continue;
        }
        if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > maxDepth)
                return makeError(ErrorKind::limit,
                                 source + ": JSON nested more than " + std::to_string(maxDepth) +
                                     " deep (at byte " + std::to_string(i) +
                                     "), more than the limit kMaxJsonDepth (limits.h)");
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return Ok{};
}

namespace {

/// The length of a well-formed UTF-8 sequence starting at text[i], 0 if there is none.
std::size_t utf8Length(std::string_view text, std::size_t i) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t length = c < 0x80         ? 1
                         : (c >> 5) == 6  ? 2
                         : (c >> 4) == 14 ? 3
                         : (c >> 3) == 30 ? 4
                                          : 0;
    if (length > 1) {
        if (i + length > text.size()) return 0;
        for (std::size_t k = 1; k < length; ++k)
            if ((static_cast<unsigned char>(text[i + k]) & 0xC0) != 0x80) return 0;
        if (length == 2 && c < 0xC2) return 0;  // overlong
    }
    return length;
}

}  // namespace

std::string validUtf8(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        const std::size_t length = utf8Length(text, i);
        if (length == 0) {
            out += "\xEF\xBF\xBD";  // U+FFFD, the replacement character
            ++i;
        } else {
            out.append(text.substr(i, length));
            i += length;
        }
    }
    return out;
}

std::string boundedExcerpt(std::string_view text, std::size_t maxChars) {
    std::string out;
    std::size_t i = 0;
    while (i < text.size() && out.size() < maxChars) {
        const auto c = static_cast<unsigned char>(text[i]);
        const std::size_t length = utf8Length(text, i);
        if (length == 0 || (length == 1 && (c < 0x20 || c == 0x7F))) {
            out += '?';
            ++i;
            continue;
        }
        out.append(text.substr(i, length));
        i += length;
    }
    if (i < text.size()) out += "...";
    return out;
}

}  // namespace plimsoll
