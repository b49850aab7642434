// Internal: refuses mesh files whose headers declare more elements than limits.h allows, or
// more than the file can hold, before an importer allocates for them.
#pragma once

#include "plimsoll/core/result.h"

#include <filesystem>
#include <istream>
#include <string>
#include <string_view>

namespace plimsoll::detail {

/// What assimp's importers trust, checked on a mesh file's bytes before they see it. PLY and
/// GLB (any extension, by their magic): declared counts against the limits and the file's size,
/// a PLY's whole body (face indices in range, polygon sizes, one element per ASCII line), a
/// GLB's chunk sizes; glTF (format "gltf" or a GLB's JSON chunk): the node tree's depth and
/// cycles; binary STL (format "stl"): the triangle count. Ok, or an error naming the file and
/// the problem. Other formats (OBJ goes through objGeometry): Ok.
Status checkMeshBytes(std::string_view bytes, const std::string& file, const std::string& format);

/// The geometry of an OBJ text, checked, for assimp: only its v, vt, vn and f lines, every
/// index of an f line naming a v / vt / vn the file defines (1..count, or -1..-count relative
/// to those defined before it) and being a number. Assimp 5.2's OBJ reader crashes on indices
/// out of range and on a material library it cannot open followed by a stray "map_" line (the
/// fuzzer found both), and the physics needs nothing but the surface and its UVs; so
/// materials, groups, lines and points never reach it. Errors name the file and the line.
Result<std::string> objGeometry(std::istream& text, const std::string& file);

}  // namespace plimsoll::detail
