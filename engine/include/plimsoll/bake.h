// The texture bake: from a mesh with a bijective UV map to the position texture (PT), the
// area-vector texture (AVT) and the coverage mask, by exact clipping of every UV triangle
// against the texel squares (DESIGN.md, "The textures"). Only covered texels are kept, in a
// compact list ordered by texel index.
#pragma once

#include "plimsoll/mesh.h"
#include "plimsoll/result.h"
#include "plimsoll/uv_layout.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace plimsoll {

/// Texture sizes the bake accepts (texels per side; any integer in range, not only powers of 2).
inline constexpr int kMinTextureSize = 16;
inline constexpr int kMaxTextureSize = 8192;

/// Called with the fraction done (0..1), from the baking threads, serialised.
using ProgressCallback = std::function<void(double fraction)>;

struct BakeSettings {
    int size = 512;          ///< texels per side, kMinTextureSize..kMaxTextureSize
    unsigned threads = 0;    ///< worker threads; 0 = all hardware threads
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
    int size = 0;              ///< N, texels per side
    UvPlacement placement;     ///< mesh uv -> texture uv used by the bake
    std::vector<std::uint32_t> texelIndex;   ///< y * N + x, ascending (repeated for shared texels)
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
};

/// Bakes the mesh's own UVs, placed by fitUvsIntoUnitSquare. The mesh must have UVs; it
/// should have passed validateMesh without errors (overlapping UVs would be counted twice).
Result<SurfaceTextures> bakeSurfaceTextures(const TriangleMesh& mesh, const BakeSettings& settings);

}  // namespace plimsoll
