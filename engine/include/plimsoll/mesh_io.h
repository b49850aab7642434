// Mesh files in and out. Import goes through assimp (OBJ, glTF/GLB, PLY, FBX, STL and every
// other format it reads); export writes Wavefront OBJ, atomically (temporary file + rename).
#pragma once

#include "plimsoll/mesh.h"
#include "plimsoll/result.h"

#include <filesystem>

namespace plimsoll {

/// Loads every mesh of the file's scene into one TriangleMesh (node transforms applied,
/// polygons triangulated, identical vertices joined). Fails with the path and the reason for a
/// missing or unreadable file, a file without triangles, or non-finite coordinates.
Result<TriangleMesh> loadMesh(const std::filesystem::path& path);

/// Writes v / vt / f lines with 17 significant digits, so a reload gives the same doubles.
Status writeObj(const TriangleMesh& mesh, const std::filesystem::path& path);

}  // namespace plimsoll
