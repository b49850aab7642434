// Internal: refuses mesh files whose headers declare more elements than limits.h allows, or
// more than the file can hold, before an importer allocates for them.
#pragma once

#include "plimsoll/core/result.h"

#include <filesystem>
#include <functional>
#include <istream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace plimsoll::detail {

/// The bytes of a file a mesh refers to (a glTF's external buffer), by the URI the mesh gives,
/// read through the importer's confined file system; empty for a mesh read from memory.
using ReadReferencedFile =
    std::function<Result<std::shared_ptr<const std::string>>(const std::string& uri)>;

/// What assimp's importers trust, checked on a mesh file's bytes before they see it. GLB (any
/// extension, by its magic): the declared chunk sizes against the file's size, then its JSON
/// chunk as glTF; glTF (format "gltf" or a GLB's JSON chunk): checkGltf; binary STL (format
/// "stl"): the triangle count; FBX (format "fbx"): the scopes' nesting and the binary arrays
/// (checkFbx). Ok, or an error naming the file and the problem. PLY goes through plyGeometry
/// and OBJ through objGeometry instead: Ok. `readReferenced` reads a glTF's external buffers.
/// Where assimp must be given other bytes than the file's (an FBX with animations: checkFbx),
/// they are put in `forAssimp`, which stays empty otherwise.
Status checkMeshBytes(std::string_view bytes, const std::string& file, const std::string& format,
                      const ReadReferencedFile& readReferenced = {},
                      std::string* forAssimp = nullptr);

/// A glTF's JSON text (a .gltf file or a GLB's JSON chunk) checked for everything assimp's
/// glTF 2 reader trusts, before it runs: nesting depth (checkJsonDepth), a JSON text both
/// parsers read alike (no repeated member names), the node tree (children exist, one parent
/// each, no cycles, depth up to kMaxGltfNodeDepth, scene roots listed once), every buffer's
/// byteLength against the bytes it really has (`glbBin`: a GLB's BIN chunk as assimp finds it,
/// for buffer 0; a data URI's decoded size; an external file's size through `readReferenced`),
/// every bufferView, accessor and sparse accessor inside its buffer with 64-bit arithmetic that
/// cannot wrap, sparse indices naming elements of their accessor, mesh primitives naming
/// accessors that fit their use, no Draco-compressed primitive, and what assimp would copy out
/// of the accessors (vertices per instance, sparse zeros) against limits.h. Errors name the
/// file and the JSON path of the value ("accessors[3].sparse.indices.bufferView: missing").
Status checkGltf(const std::string& file, std::string_view jsonText,
                 std::optional<std::string_view> glbBin, const ReadReferencedFile& readReferenced);

/// An FBX file's scopes (ASCII braces outside strings and comments, binary nested node
/// records) nested no deeper than kMaxFbxDepth, found before any recursion goes deeper (a
/// binary file's in one linear pass). In a binary file every array property also holds exactly
/// its elements, raw or as zlib data that
/// inflates to them, and all together no more than kMaxFbxInflatedBytes. Then the element tree
/// as assimp's parser builds it, checked for what assimp reads without looking (fbx_check.cpp:
/// layer indices, per-polygon material lists, models that are their own ancestors). Where the
/// file has objects Plimsoll does not read (anything but models, materials and polygon meshes)
/// and `forAssimp` is given, it receives the bytes assimp is to read: the same, with each such
/// object's name changed at its last letter, so that assimp reads none of them.
Status checkFbx(const std::string& file, std::string_view bytes, std::string* forAssimp = nullptr);

/// The format a mesh file is read as: one of "obj", "ply", "stl", "fbx", "gltf", "glb", chosen
/// by the bytes' content first (an OBJ named ".OBJ.bak" is read, and checked, as OBJ) and by
/// `format` (the lower-case extension) where the content is not recognised. Every other format
/// (COLLADA, X, 3MF, OFF, ...) is refused naming what it is, before assimp sees it.
Result<std::string> meshFormat(std::string_view bytes, const std::string& format,
                               const std::string& file);

/// Whether a mesh file is read as PLY: format "ply", or bytes that start "ply" whatever the
/// extension (assimp would pick its PLY reader by that signature).
bool isPly(std::string_view bytes, const std::string& format);

/// A PLY file read strictly (ASCII or binary, either byte order) and written back as the
/// canonical PLY that is all assimp's PLY reader ever sees: binary little-endian, float x, y,
/// z (and u, v where the file has a texture coordinate) and the faces' vertex_indices; colours,
/// normals and other elements are left out, as the physics uses none of them. Declared counts
/// are checked against limits.h and the file's size before anything is allocated for them,
/// every face index against the vertex count, every ASCII element against its line. Errors
/// name the file, the element and (ASCII) the line.
Result<std::string> plyGeometry(std::string_view bytes, const std::string& file);

/// The geometry of an OBJ text, checked, for assimp: only its v, vt, vn and f lines, every
/// index of an f line naming a v / vt / vn the file defines (1..count, or -1..-count relative
/// to those defined before it) and being a number. Assimp 5.2's OBJ reader crashes on indices
/// out of range and on a material library it cannot open followed by a stray "map_" line (the
/// fuzzer found both), and the physics needs nothing but the surface and its UVs; so
/// materials, groups, lines and points never reach it. Errors name the file and the line.
Result<std::string> objGeometry(std::istream& text, const std::string& file);

}  // namespace plimsoll::detail
