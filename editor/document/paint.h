// The painting engine: brushes over the surface, not over the image. Every pixel of a painted
// map gets the surface points that map into it (the bake's per-texel area centroids at the
// map's own resolution), and a 3D dab paints every pixel with a point within the brush radius
// of the hit point, in object-space (= world) distance: strokes cross UV seams and chart borders
// without a trace. No GL here: the editor, `plimsoll edit --script` and the tests share it.
#pragma once

#include "plimsoll/mesh.h"
#include "plimsoll/painted_map.h"
#include "plimsoll/result.h"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace plimsoll::editor {

/// The surface points of every pixel of a map of one size over one mesh's UVs.
struct PaintSurface {
    int width = 0;
    int height = 0;
    /// One sample per (pixel, UV island) piece of surface, as the bake's entries.
    std::vector<std::uint32_t> pixel;        ///< y * width + x, row 0 at the top (v = 1)
    std::vector<Eigen::Vector3f> position;   ///< object space, m
    std::vector<std::uint32_t> island;       ///< UV island id (uvIslands)
    std::size_t sampleCount() const { return pixel.size(); }
};

/// Bakes the mesh's UV atlas at the map's resolution (square bake of max(width, height) texels,
/// each texel centre taken to its map pixel). The mesh needs UVs.
Result<PaintSurface> buildPaintSurface(const TriangleMesh& mesh, int width, int height);

enum class BrushMode { Paint, Erase, Smooth };
enum class Falloff { Smooth, Linear, Constant };

struct Brush {
    BrushMode mode = BrushMode::Paint;
    double radius = 0.05;    ///< m, object space (= world: bodies are not scaled)
    double strength = 1.0;   ///< 0..1, how far a stroke moves a pixel toward its target
    double value = 1.0;      ///< 0..1, the paint mode's target
    Falloff falloff = Falloff::Smooth;
    bool mirrorX = false;    ///< also paint at (-x, y, z)
};

/// Weight 0..1 of a point at distance d from the dab centre.
double falloffWeight(Falloff falloff, double distance, double radius);

/// What a stroke changed: the pixels, their values before and after.
struct PixelChange {
    std::vector<std::uint32_t> pixels;
    std::vector<float> before;
    std::vector<float> after;
    bool empty() const { return pixels.empty(); }
};

/// A stroke through `points` (object space; consecutive points are joined with dabs a quarter
/// radius apart). Paint and erase move each pixel toward the target by strength times its
/// largest weight along the stroke (a stroke never builds up over itself); smooth blends each
/// dab toward the weighted mean of the values under it. `map` is not modified.
PixelChange strokeChange(const PaintedMap& map, const PaintSurface& surface, const Brush& brush,
                         std::span<const Eigen::Vector3d> points);

/// Sets every pixel of the UV island nearest to `point` (and of the mirrored point's island with
/// mirrorX) to `value`.
PixelChange fillIslandChange(const PaintedMap& map, const PaintSurface& surface,
                             const Eigen::Vector3d& point, double value, bool mirrorX);

/// Sets every pixel to `value`.
PixelChange fillAllChange(const PaintedMap& map, double value);

/// The map's value at the surface sample nearest to `point` (the value picker).
std::optional<double> pickValue(const PaintedMap& map, const PaintSurface& surface,
                                const Eigen::Vector3d& point);

void applyValues(PaintedMap& map, const std::vector<std::uint32_t>& pixels,
                 const std::vector<float>& values);

/// A point on the mesh: where a ray hits it, or where a UV lands.
struct SurfaceHit {
    Eigen::Vector3d point;   ///< object space
    std::uint32_t triangle = 0;
    double distance = 0;     ///< along the ray (ray hits only)
};

/// Nearest hit of the ray origin + t direction, t >= 0 (object space), with either face.
std::optional<SurfaceHit> raycast(const TriangleMesh& mesh, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& direction);

/// The surface point whose mesh uv is `uv` (for painting in the UV view), if a triangle has it.
std::optional<SurfaceHit> surfaceAtUv(const TriangleMesh& mesh, const Eigen::Vector2d& uv);

}  // namespace plimsoll::editor
