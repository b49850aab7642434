// Mesh files in and out. Import goes through assimp (OBJ, glTF/GLB, PLY, FBX, STL and every
// other format it reads); export writes Wavefront OBJ, atomically (temporary file + rename).
#pragma once

#include "plimsoll/geometry/mesh.h"
#include "plimsoll/core/result.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace plimsoll {

struct MeshLoadOptions {
    /// Join identical vertices (same position, UV and every other attribute: OBJ files index
    /// positions and UVs separately, so each face corner is a vertex of its own until joined).
    /// Off for the frames of a deforming mesh: which vertices coincide differs between frames,
    /// and so would the joined vertex count and indices.
    bool joinIdenticalVertices = true;
};

/// Loads every mesh of the file's scene into one TriangleMesh (node transforms applied,
/// polygons triangulated, identical vertices joined unless options say not). Fails with the
/// path and the reason for a missing, unreadable or oversized file, or a file without
/// triangles. NaN or Inf coordinates load as they are: validateMesh reports them
/// (ProblemKind::NonFinite), so the user sees every problem of the mesh at once.
Result<TriangleMesh> loadMesh(const std::filesystem::path& path, MeshLoadOptions options = {});

/// As loadMesh, from the file's bytes: `format` is the extension assimp picks its reader by
/// ("obj", "ply", ...), `source` names the mesh in messages. Files the mesh refers to (an OBJ's
/// material library) are not read. The fuzz target reads meshes through this.
Result<TriangleMesh> loadMeshFromMemory(std::string_view bytes, const std::string& format,
                                        const std::string& source, MeshLoadOptions options = {});

/// Writes v / vt / f lines with 17 significant digits, so a reload gives the same doubles.
Status writeObj(const TriangleMesh& mesh, const std::filesystem::path& path);

/// Loads the frames of a deforming mesh, one file each, without joining vertices (joining
/// depends on which positions coincide, which differs between frames). Every frame must have
/// the first frame's vertex count, triangles and UVs; the error names the file and the
/// first difference.
Result<std::vector<TriangleMesh>> loadMeshFrames(const std::vector<std::filesystem::path>& paths);

}  // namespace plimsoll
