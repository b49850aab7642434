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

/// "1.2 GB": an amount of memory for messages.
std::string formatBytes(double bytes);

}  // namespace plimsoll
