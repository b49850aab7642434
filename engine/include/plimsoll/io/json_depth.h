// JSON is refused past a stated nesting depth before any parser or formatter sees it: the
// recursive code that reads, prints or destroys a document (nlohmann's dump(), assimp's
// rapidjson reader of glTF) overflows its stack on 100000 nested arrays, while every real
// Plimsoll file nests under ten levels and real glTF extras a few tens.
#pragma once

#include <cstdint>
#include "plimsoll/core/result.h"

#include <string>
#include <string_view>

namespace plimsoll {

/// Nesting depth of any JSON document read (projects, graphs, scripts, manifests, caches,
/// layer files, autosaves, glTF): checked by a linear scan before parsing, since the recursive
/// readers and printers (nlohmann's dump(), assimp's glTF reader) overflow their stacks on deep
/// nesting. Plimsoll's own files nest under ten levels; glTF extras a few tens.
inline constexpr std::uint64_t kMaxJsonDepth = 128;

/// Ok if no array or object in `text` nests deeper than `maxDepth` (brackets inside strings
/// not counted; the text need not be valid JSON); else "SOURCE: JSON nested more than N deep
/// (at byte B), more than the limit kMaxJsonDepth (json_depth.h)". One linear pass, no recursion.
Status checkJsonDepth(std::string_view text, const std::string& source,
                      std::uint64_t maxDepth = kMaxJsonDepth);

/// At most `maxChars` of `text` for an error message, "..." marking a cut; control bytes and
/// bytes that are not UTF-8 shown as '?', so a message stays one valid UTF-8 line.
std::string boundedExcerpt(std::string_view text, std::size_t maxChars = 60);

}  // namespace plimsoll
