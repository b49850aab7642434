// JSON is refused past a stated nesting depth before any parser or formatter sees it: the
// recursive code that reads, prints or destroys a document (nlohmann's dump(), assimp's
// rapidjson reader of glTF) overflows its stack on 100000 nested arrays, while every real
// Plimsoll file nests under ten levels and real glTF extras a few tens.
#pragma once

#include <cstdint>
#include "plimsoll/core/limits.h"
#include "plimsoll/core/result.h"

#include <string>
#include <string_view>

namespace plimsoll {

/// Ok if no array or object in `text` nests deeper than `maxDepth` (brackets inside strings
/// not counted; the text need not be valid JSON); else "SOURCE: JSON nested more than N deep
/// (at byte B), more than the limit kMaxJsonDepth (limits.h)". One linear pass, no recursion.
Status checkJsonDepth(std::string_view text, const std::string& source,
                      std::uint64_t maxDepth = kMaxJsonDepth);

/// At most `maxChars` of `text` for an error message, "..." marking a cut; control bytes and
/// bytes that are not UTF-8 shown as '?', so a message stays one valid UTF-8 line.
std::string boundedExcerpt(std::string_view text, std::size_t maxChars = 60);

/// `text` with every byte that does not begin a well-formed UTF-8 sequence written as U+FFFD:
/// for reports (JUnit XML, summaries) that quote names and messages from any file.
std::string validUtf8(std::string_view text);

namespace detail {
template <class JsonValue>
void appendJsonExcerpt(const JsonValue& value, std::size_t maxChars, std::string& out) {
    if (out.size() >= maxChars) return;
    if (value.is_string()) {
        out += '"' + boundedExcerpt(value.template get_ref<const std::string&>(), maxChars) + '"';
    } else if (value.is_array() || value.is_object()) {
        out += value.is_array() ? '[' : '{';
        for (auto it = value.begin(); it != value.end() && out.size() < maxChars; ++it) {
            if (it != value.begin()) out += ", ";
            if (value.is_object()) out += '"' + boundedExcerpt(it.key(), maxChars) + "\": ";
            appendJsonExcerpt(*it, maxChars, out);
        }
        out += value.is_array() ? ']' : '}';
    } else {
        out += value.dump();  // a number, a boolean or null: a few characters
    }
}
}  // namespace detail

/// A JSON value (nlohmann's) as text for an error message: at most `maxChars` as
/// boundedExcerpt cuts it, written only as far as that, never a full dump() (which recurses
/// through every level and writes every byte of a large value). Each level writes a bracket,
/// so the recursion is at most `maxChars` deep whatever the value's depth.
template <class JsonValue>
std::string jsonExcerpt(const JsonValue& value, std::size_t maxChars = 60) {
    std::string out;
    detail::appendJsonExcerpt(value, maxChars, out);
    return boundedExcerpt(out, maxChars);
}

}  // namespace plimsoll
