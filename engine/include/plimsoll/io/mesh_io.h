// Mesh files in and out. Import goes through assimp (OBJ, glTF/GLB, PLY, FBX, STL and every
// other format it reads); export writes Wavefront OBJ, atomically (temporary file + rename).
#pragma once

#include "plimsoll/geometry/mesh.h"
#include "plimsoll/core/result.h"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plimsoll {

struct MeshLoadOptions {
    /// Join identical vertices (same position, UV and every other attribute: OBJ files index
    /// positions and UVs separately, so each face corner is a vertex of its own until joined).
    /// Off for the frames of a deforming mesh: which vertices coincide differs between frames,
    /// and so would the joined vertex count and indices.
    bool joinIdenticalVertices = true;
    /// Metres per file unit chosen by the user (a project's "unit", the CLI's --unit); 0 keeps
    /// the file's own unit (FBX UnitScaleFactor, glTF metres) and metres where the format has
    /// none (OBJ, STL, PLY).
    double unitScale = 0;
};

/// One mesh of the file's scene, as its triangles sit in the loaded TriangleMesh.
struct MeshPart {
    std::string name;
    std::size_t firstTriangle = 0;
    std::size_t triangleCount = 0;
    bool hasUvs = false;  ///< whether the file gives this part texture coordinates
};

/// What a load found besides the triangles: the unit applied and the file's parts.
struct MeshFileFacts {
    double unitScale = 1.0;  ///< metres per file unit, applied to the positions
    /// Where unitScale comes from, for reports: "FBX UnitScaleFactor 1 (centimetres)",
    /// "glTF (metres)", "no unit in the file: metres", "--unit / project unit".
    std::string unitSource;
    std::vector<MeshPart> parts;
    /// Parts with UVs and parts without: the UVs are kept, and the triangles of the parts
    /// without get (0, 0) at every corner, which validateMesh reports as zero UV area.
    bool someUvsMissing() const;
};

/// A length unit by name ("m", "cm", "mm", "km", "in", "ft", "yd") or as metres per unit (a
/// finite positive number); nothing for anything else.
std::optional<double> parseLengthUnit(const std::string& text);

/// A readable name for metres per unit: "metres", "centimetres", ..., or "x m" otherwise.
std::string lengthUnitName(double metresPerUnit);

/// Loads every mesh of the file's scene into one TriangleMesh (node transforms applied,
/// polygons triangulated, identical vertices joined unless options say not, positions in
/// metres: see MeshLoadOptions::unitScale); `facts`, when given, receives the unit applied
/// and the parts. Fails with the
/// path and the reason for a missing, unreadable or oversized file, or a file without
/// triangles. NaN or Inf coordinates load as they are: validateMesh reports them
/// (ProblemKind::NonFinite), so the user sees every problem of the mesh at once.
Result<TriangleMesh> loadMesh(const std::filesystem::path& path, MeshLoadOptions options = {},
                              MeshFileFacts* facts = nullptr);

/// As loadMesh, from the file's bytes: `format` is the extension assimp picks its reader by
/// ("obj", "ply", ...), `source` names the mesh in messages. Files the mesh refers to (an OBJ's
/// material library) are not read. The fuzz target reads meshes through this.
Result<TriangleMesh> loadMeshFromMemory(std::string_view bytes, const std::string& format,
                                        const std::string& source, MeshLoadOptions options = {},
                                        MeshFileFacts* facts = nullptr);

/// Writes v / vt / f lines with 17 significant digits, so a reload gives the same doubles.
Status writeObj(const TriangleMesh& mesh, const std::filesystem::path& path);

/// Loads the frames of a deforming mesh, one file each, without joining vertices (joining
/// depends on which positions coincide, which differs between frames). Every frame must have
/// the first frame's vertex count, triangles and UVs; the error names the file and the
/// first difference.
Result<std::vector<TriangleMesh>> loadMeshFrames(const std::vector<std::filesystem::path>& paths);

}  // namespace plimsoll
