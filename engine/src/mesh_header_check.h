// Internal: refuses mesh files whose headers declare more elements than limits.h allows, or
// more than the file can hold, before an importer allocates for them.
#pragma once

#include "plimsoll/result.h"

#include <filesystem>
#include <istream>
#include <string>

namespace plimsoll::detail {

/// PLY and GLB (any extension, by their magic) and binary STL (.stl): Ok, or an error naming
/// the file, the declared count and the limit (or the bytes missing). Other formats (OBJ goes
/// through objGeometry): Ok.
Status checkMeshHeader(const std::filesystem::path& path);

/// The geometry of an OBJ text, checked, for assimp: only its v, vt, vn and f lines, every
/// index of an f line naming a v / vt / vn the file defines (1..count, or -1..-count relative
/// to those defined before it) and being a number. Assimp 5.2's OBJ reader crashes on indices
/// out of range and on a material library it cannot open followed by a stray "map_" line (the
/// fuzzer found both), and the physics needs nothing but the surface and its UVs; so
/// materials, groups, lines and points never reach it. Errors name the file and the line.
Result<std::string> objGeometry(std::istream& text, const std::string& file);

}  // namespace plimsoll::detail
