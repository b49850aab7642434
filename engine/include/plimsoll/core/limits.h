// Size limits, checked before anything large is allocated: a file that asks for more is
// refused with an error naming the limit, the amount asked for and the file, instead of an
// abort, a std::bad_alloc or the machine swapping. All limits live here, each with its reason.
#pragma once

#include <cstdint>
#include <string>

namespace plimsoll {

/// Physics texture side, texels (any integer in range, not only powers of 2). 16: below that a
/// texel is coarser than any mesh detail worth baking. 8192: 67M texels; a baked sample takes
/// ~72 bytes (position, area vector, area, coverage, index, in double), so a fully covered
/// 8192^2 texture needs ~5 GB, the most a workstation should be asked for. A 100000^2 texture
/// (750 GB) is refused when the project is read.
inline constexpr int kMinTextureSize = 16;
inline constexpr int kMaxTextureSize = 8192;

/// Triangles in one mesh file. 20M: a scanned statue is ~10M; TriangleMesh keeps ~100 bytes per
/// triangle with its vertices and validation adds edge maps of about the same, so 20M triangles
/// is ~4 GB. A PLY or STL header claiming more is refused before the importer reserves memory
/// for it.
inline constexpr std::uint64_t kMaxTriangles = 20'000'000;
/// Vertices in one mesh file: three per triangle, the most an unwelded mesh has.
inline constexpr std::uint64_t kMaxVertices = 3 * kMaxTriangles;

/// Water graph size. Nodes are compartments an artist places or segmentation finds (tens to
/// hundreds); 100000 leaves room for generated graphs while a node's per-step state (~100 bytes
/// with its neighbour lists) stays far below a texture's. Pipes: 16 per node on average.
inline constexpr std::uint64_t kMaxGraphNodes = 100'000;
inline constexpr std::uint64_t kMaxGraphPipes = 16 * kMaxGraphNodes;

/// JSON files (projects, graphs, manifests) are read whole: 256 MB is far beyond any real one
/// (a 100000-node graph is ~20 MB) and keeps a wrong file (a mesh or a disk image picked by
/// mistake) from being read into memory.
inline constexpr std::uint64_t kMaxJsonFileBytes = 256ull << 20;

/// Mesh files are read whole (assimp parses from memory): 2 GB holds a binary STL of
/// kMaxTriangles (1 GB) and an ASCII PLY of it; a wrong file (a disk image) is refused unread.
inline constexpr std::uint64_t kMaxMeshFileBytes = 2ull << 30;

/// Nesting depth of a glTF node tree. Assimp walks the tree recursively, so a chain of 20000
/// nested nodes overflows its stack; real scenes nest a few levels (rigs: tens).
inline constexpr std::uint64_t kMaxGltfNodeDepth = 256;

/// Bytes of glTF accessors that have no bufferView, all together: such an accessor is all zeros
/// (with its sparse values patched in), and assimp allocates it whole, count times element
/// size, from a few bytes of JSON (a 1.7 KB file asked for 1.2 GB). Real files use them for
/// morph targets: a position target of a 1M-vertex mesh is 12 MB; 256 MB holds one of 22M.
inline constexpr std::uint64_t kMaxGltfZeroFilledBytes = 256ull << 20;

/// Nesting depth of any JSON document read (projects, graphs, scripts, manifests, caches,
/// layer files, autosaves, glTF): checked by a linear scan before parsing (json_depth.h),
/// since the recursive readers and printers (nlohmann's dump(), assimp's glTF reader) overflow
/// their stacks on deep nesting. Plimsoll's own files nest under ten levels; glTF extras a few
/// tens.
inline constexpr std::uint64_t kMaxJsonDepth = 128;

/// Nesting depth of an FBX file's scopes (ASCII braces, binary node records). Assimp reads
/// both forms recursively, one stack frame set per scope, so 50000 nested braces overflow its
/// stack; real files nest under ten levels.
inline constexpr std::uint64_t kMaxFbxDepth = 128;

/// Models nested in an FBX file's model tree (parent links between models). Assimp converts the
/// tree recursively, a few hundred bytes of stack per model; real skeletons and scene
/// hierarchies are under a hundred deep.
inline constexpr std::uint64_t kMaxFbxModelDepth = 1024;

/// Bytes of an FBX property's name (a "P" element's first value). Assimp keeps a material's
/// properties under "$raw." + the name in a 1024-byte key and aborts on a longer one; real
/// names are a few tens of bytes.
inline constexpr std::uint64_t kMaxFbxPropertyName = 512;

/// A binary FBX file's arrays inflated, all together. Assimp allocates each array whole from
/// the count the file states before inflating it, so a few bytes could ask for gigabytes; real
/// files' arrays add up to about the size of the uncompressed file, under kMaxMeshFileBytes.
inline constexpr std::uint64_t kMaxFbxInflatedBytes = kMaxMeshFileBytes;

/// Corners of one polygon in a mesh file. Assimp's triangulation of a polygon is quadratic in
/// its corners (one 200k-corner OBJ face took 7 minutes); real polygons have a handful, fans of
/// caps a few hundred.
inline constexpr std::uint64_t kMaxFaceCorners = 4096;

/// Side of a painted map (PNG) in pixels, checked from the PNG header before decoding: the map
/// is sampled at the physics texture's texels, so a larger one holds nothing the texture can
/// use, and a 16384^2 16-bit image needs 512 MB decoded (a 0.5 MB file can declare it).
inline constexpr int kMaxPaintedMapSide = kMaxTextureSize;

/// Other binary files read whole (painted maps, edit scripts, EXR images): 1 GB, beyond a
/// full kMaxPaintedMapSide^2 16-bit PNG stored uncompressed (128 MB) or a baked 8192^2 EXR.
inline constexpr std::uint64_t kMaxDataFileBytes = 1ull << 30;

/// Frames of one headless run (duration / time step). 1e9: at a microsecond a frame, a quarter
/// of an hour; a duration of 1e300 s or a time step of 1e-300 s is refused up front, not
/// converted to an integer it does not fit.
inline constexpr std::uint64_t kMaxSimulationFrames = 1'000'000'000;

/// "1.2 GB": an amount of memory for messages.
std::string formatBytes(double bytes);

}  // namespace plimsoll
