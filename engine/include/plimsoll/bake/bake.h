// The texture bake: from a mesh with a bijective UV map to the position texture (PT), the
// area-vector texture (AVT) and the coverage mask, by exact clipping of every UV triangle
// against the texel squares (docs/design.md, "The textures"). Only covered texels are kept, in a
// compact list ordered by texel index.
#pragma once

#include "plimsoll/core/limits.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/core/result.h"
#include "plimsoll/geometry/uv_layout.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace plimsoll {

// Texture sizes the bake accepts: kMinTextureSize..kMaxTextureSize (limits.h).

/// Called with the fraction done (0..1), from the baking threads, serialised.
using ProgressCallback = std::function<void(double fraction)>;

struct BakeSettings {
    int size = 512;        ///< texels per side, kMinTextureSize..kMaxTextureSize
    unsigned threads = 0;  ///< worker threads; 0 = all hardware threads
    /// Sub-texel refinement: a triangle whose texels span, in their longest direction on the
    /// surface, more than this many times the mesh's typical texel side is cut on a finer grid
    /// (up to 64 x 64 cells a texel), each cell its own entry. Lower is more accurate on
    /// distorted UV maps and costs entries; 0 turns refinement off (one entry per texel and
    /// island, the paper's method).
    double maxTexelStretch = 4.0;
    ProgressCallback progress;
};

/// Texel (x, y) covers texture uv in [x/N, (x+1)/N] x [y/N, (y+1)/N]; its index is y * N + x
/// (row 0 at v = 0, as glTexImage2D lays rows out).
///
/// One entry per covered texel and UV island: a texel on the border of two islands holds two
/// pieces of surface that may lie far apart on the body, and gets one entry for each (in the
/// order the islands reached it), so every entry's point and area vector describe one connected
/// piece of surface. All per-entry vectors have the same length.
struct SurfaceTextures {
    int size = 0;                           ///< N, texels per side
    UvPlacement placement;                  ///< mesh uv -> texture uv used by the bake
    std::vector<std::uint32_t> texelIndex;  ///< y * N + x, ascending (repeated for shared texels)
    /// PT: area centroid of the surface that maps into the texel, object space, m.
    std::vector<Eigen::Vector3d> position;
    /// AVT: integral of n dS over that surface, m^2 (outward normal).
    std::vector<Eigen::Vector3d> areaVector;
    /// Surface area that maps into the texel, m^2 (>= |areaVector|; larger across creases).
    std::vector<double> area;
    /// Share of the texel's UV square covered by the atlas, 0..1.
    std::vector<double> coverage;

    /// Entries (what every per-texel sum runs over).
    std::size_t coveredCount() const { return texelIndex.size(); }
    /// Distinct covered texels (entries minus the extra entries of shared texels).
    std::size_t distinctTexelCount() const;
    /// Covered UV area as a share of the whole texture.
    double uvCoverage() const;
    double surfaceArea() const;
    /// |sum A_i| / sum |A_i|: zero for a closed surface up to rounding.
    double closureError() const;
    /// Mean of the positions weighted by area: the reference point for sums (keeps digits).
    Eigen::Vector3d areaCentroid() const;
    /// Texel world-area spread: surface area per covered texel area (area / coverage, so that
    /// partly covered border texels count at their density), largest over smallest among the
    /// entries, the `tail` share at either extreme ignored. 1 for a uniform atlas.
    double texelAreaSpread(double tail = 0.01) const;
};

/// One piece of a triangle clipped to an entry's texel (or sub-texel cell). The map from UV to
/// the surface is affine on a triangle, so for any vertex positions the piece's centroid is the
/// barycentric combination below and its area vector `share` times the triangle's: a deforming
/// mesh that keeps its triangles and UVs regathers its textures from these (deform.h).
struct SurfacePiece {
    std::uint32_t triangle;  ///< index into the mesh's triangles
    /// (b1, b2) of the piece's UV centroid: point = p0 + b1 (p1 - p0) + b2 (p2 - p0). Double,
    /// not float: float would move the point by 1e-7 of the triangle, and a regather of the
    /// baked mesh would no longer reproduce the bake.
    double barycentric[2];
    double share;  ///< of the triangle's UV area, and so of its area and area vector
};

/// The pieces accumulated into every entry of a bake, in the order they were accumulated.
struct SurfacePieceTable {
    /// Pieces of entry i are pieces[firstPiece[i] .. firstPiece[i + 1]); entries + 1 values.
    std::vector<std::uint32_t> firstPiece;
    std::vector<SurfacePiece> pieces;
    std::size_t triangleCount = 0;  ///< of the baked mesh (regatherSurface asserts it)

    std::size_t entryCount() const { return firstPiece.empty() ? 0 : firstPiece.size() - 1; }
};

/// Bakes the mesh's own UVs, placed by fitUvsIntoUnitSquare. The mesh must have UVs; it
/// should have passed validateMesh without errors (overlapping UVs would be counted twice).
/// With `pieces`, also records which triangle pieces make up every entry, for regatherSurface
/// (32 bytes a piece; the buoy has 1.3 pieces an entry at N = 512, and records in 1.5 times
/// the bake's time); without, the bake does no extra work.
Result<SurfaceTextures> bakeSurfaceTextures(const TriangleMesh& mesh, const BakeSettings& settings,
                                            SurfacePieceTable* pieces = nullptr);

}  // namespace plimsoll
