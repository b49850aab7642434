// The painting engine: brushes over the surface, not over the image. Every pixel of a painted
// map gets the surface points that map into it (the bake's per-texel area centroids at the
// map's own resolution), and a 3D dab paints every pixel with a point within the brush radius
// of the hit point, in object-space (= world) distance: strokes cross UV seams and chart borders
// without a trace. No GL here: the editor, `plimsoll edit --script` and the tests share it.
#pragma once

#include "plimsoll/geometry/mesh.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/core/result.h"

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>
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
    std::vector<std::uint32_t> pixel;       ///< y * width + x, row 0 at the top (v = 1)
    std::vector<Eigen::Vector3f> position;  ///< object space, m
    std::vector<std::uint32_t> island;      ///< UV island id (uvIslands)
    /// Outward unit normal of the surface in the texel (its area vector's direction), object
    /// space: the brush's normal falloff and front-faces-only test it against the view.
    std::vector<Eigen::Vector3f> normal;
    /// Half the pixel's sides on the surface, object space: its u side and its v side (the
    /// surface's d position / d uv on the sample's first triangle, times half a pixel, at most
    /// that triangle's longest edge). The pixel's piece of surface lies within the
    /// parallelogram position +- halfU +- halfV, and a brush that reaches any of it paints the
    /// pixel: a brush smaller than a pixel still paints every pixel it passes over.
    std::vector<Eigen::Vector3f> halfU;
    std::vector<Eigen::Vector3f> halfV;
    std::size_t sampleCount() const { return pixel.size(); }
};

/// Bakes the mesh's UV atlas on the map's own pixel grid (one texel per pixel, the grid reaching
/// over every UV the mesh has; a UV outside 0..1 belongs to the edge pixel, as the physics reads
/// it), so every pixel a triangle covers gets its points. The mesh needs UVs; an error when
/// its UVs span more than kMaxTextureSize pixels.
Result<PaintSurface> buildPaintSurface(const TriangleMesh& mesh, int width, int height);

enum class BrushMode { Paint, Erase, Smooth };
/// The weight's fall from the dab centre (s = distance / radius, p = 1 - s): Smooth (1 - s^2)^2,
/// Linear p, Constant 1, and Blender's presets Sphere sqrt(1 - s^2), Root sqrt(p), Sharp p^2 and
/// InverseSquare p (2 - p); Custom: the brush's own curve (FalloffCurve, Blender's "Custom").
enum class Falloff { Smooth, Linear, Constant, Sphere, Root, Sharp, InverseSquare, Custom };
inline constexpr int kFalloffCount = 8;
inline constexpr int kFalloffPresetCount = 7;  ///< the ones with a formula: all but Custom
/// "smooth", "linear", ... (edit scripts and the brush panel); parseFalloff reads them back.
const char* falloffName(Falloff falloff);
std::optional<Falloff> parseFalloff(const std::string& name);

/// Most control points of a falloff curve.
inline constexpr int kMaxFalloffPoints = 32;

/// A falloff drawn by hand (Blender's custom brush curve): control points (s, weight), s the
/// distance over the radius from 0 (centre) to 1 (rim), weight 0..1, s increasing, the first at
/// s = 0 and the last at s = 1. Between points a monotone cubic (Fritsch and Carlson 1980): it
/// passes through every point and never overshoots them, so a curve drawn falling never rises
/// and a flat stretch stays flat.
struct FalloffCurve {
    std::vector<Eigen::Vector2d> points{Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 0)};

    /// The weight at s (clamped to 0..1).
    double operator()(double s) const;
    /// `count` points (2..kMaxFalloffPoints) on a preset's formula, evenly spaced in s: the
    /// curve editor's starting shapes. Sphere and Root rise without bound at the rim, which
    /// a cubic through nine points follows only to about 0.1.
    static FalloffCurve preset(Falloff falloff, int count = 9);
    /// Any list of points made valid: non-finite ones dropped, each clamped to the unit
    /// square, sorted by s, points closer than 0.01 in s merged, ends added at s = 0 and 1
    /// (keeping the nearest point's weight), at most kMaxFalloffPoints.
    static FalloffCurve sanitised(std::vector<Eigen::Vector2d> points);
    bool operator==(const FalloffCurve&) const = default;
};

/// Longest lazy-mouse string, screen pixels.
inline constexpr double kMaxLazyRadius = 200.0;

/// Most copies radial symmetry makes of a dab.
inline constexpr int kMaxRadialCopies = 64;

struct Brush {
    BrushMode mode = BrushMode::Paint;
    double radius = 0.05;   ///< m, object space (= world: bodies are not scaled)
    double strength = 1.0;  ///< 0..1, how far a stroke moves a pixel toward its target
    double value = 1.0;     ///< 0..1, the paint mode's target
    Falloff falloff = Falloff::Smooth;
    FalloffCurve curve = FalloffCurve::preset(Falloff::Smooth);  ///< used when falloff is Custom
    /// Dabs along a stroke at most this many radii apart (Blender's spacing; 0.25 paints a
    /// solid line, above 2 leaves separate dots).
    double spacing = 0.25;
    bool mirrorX = false;  ///< also paint at (-x, y, z)
    bool mirrorY = false;  ///< also paint at (x, -y, z)
    bool mirrorZ = false;  ///< also paint at (x, y, -z)
    /// Radial symmetry about the object y axis (a buoy's or a hull's vertical): every dab and
    /// its mirror images repeated this many times, evenly turned (1: off; at most
    /// kMaxRadialCopies).
    int radial = 1;
    /// Lazy mouse (Blender's stabilise stroke): the brush trails the cursor on a string this
    /// many screen pixels long (0: off). See LazyMouse.
    double lazyRadius = 0;
    /// An alpha (Painter) or stencil image: each dab's weight is also multiplied by this grey
    /// image, laid square over the dab (side 2 radius) in the plane across `alphaAxis`, row 0
    /// at the top. Null: none.
    std::shared_ptr<const PaintedMap> alpha;
    /// Object space, toward the viewer when the stroke starts: the image then lies upright on
    /// screen (its right along y x axis, its top along axis x right).
    Eigen::Vector3d alphaAxis = Eigen::Vector3d::UnitZ();
    std::string alphaPath;  ///< the image's file, kept between sessions ("" : none)
    /// Blender's normal falloff: a texel whose normal turns more than this from the direction
    /// toward the viewer (alphaAxis, set at the stroke's start; mirrored and turned with each
    /// symmetric dab) gets no paint; full weight up to half the angle, fading linearly between.
    /// Degrees; 180 (or more): off.
    double normalAngle = 180.0;
    /// Backface culling: texels facing away from the viewer (normal . toward viewer <= 0) get
    /// no paint, whatever normalAngle says.
    bool frontFacesOnly = false;
    /// Occlusion: texels hidden from the viewer behind other parts of the surface get no
    /// paint. Seen through a depth grid of the surface's samples with cells a quarter of the
    /// radius across at the stroke: along alphaAxis (orthographic), or from `eye`.
    bool occlusion = false;
    /// A perspective view's camera, object space (set with alphaAxis at the stroke's start;
    /// none: orthographic). Occlusion then sees the surface from this point, and the normal
    /// falloff and front-faces-only take each texel's own direction toward it, as Blender does
    /// in a perspective view. Mirrored and turned with each symmetric dab.
    std::optional<Eigen::Vector3d> eye;
};

/// The weight a texel of normal `normal` keeps under the brush's normal falloff and front-
/// faces-only, the viewer in direction `towardViewer` (both unit, object space): 0..1.
double facingWeight(const Brush& brush, const Eigen::Vector3d& normal,
                    const Eigen::Vector3d& towardViewer);

/// The string of the lazy mouse: the brush stays put while the cursor moves within `radius`
/// pixels of it, and is pulled along the string when the cursor goes further, so a shaky hand
/// draws a smooth line and a sharp corner is rounded off.
class LazyMouse {
public:
    LazyMouse() = default;
    explicit LazyMouse(double radius) : radius_(std::max(0.0, radius)) {}
    /// The brush after the cursor moved to `cursor` (the first call: the cursor itself).
    Eigen::Vector2d follow(const Eigen::Vector2d& cursor);
    const std::optional<Eigen::Vector2d>& brush() const { return brush_; }

private:
    double radius_ = 0;
    std::optional<Eigen::Vector2d> brush_;
};

/// A line stroke's screen samples (Shift-click from the last stroke's end): `from` to `to`
/// at most `step` pixels apart, both ends included; each is then picked on the surface.
std::vector<Eigen::Vector2d> lineSamples(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                         double step);

/// Loads a grey (or colour: its first channel) PNG as the brush's alpha image and keeps its
/// path; on failure the brush is unchanged and the error names the file.
Status loadBrushAlpha(Brush& brush, const std::filesystem::path& path);

/// The brush's weight at `offset` (object space) from a dab's centre: the falloff times the
/// alpha image's value there (1 without one); 0 outside the radius.
double dabWeight(const Brush& brush, const Eigen::Vector3d& offset);

/// Weight 0..1 of a point at distance d from the dab centre; Custom reads `curve` (the
/// default FalloffCurve, linear, when none is given).
double falloffWeight(Falloff falloff, double distance, double radius,
                     const FalloffCurve* curve = nullptr);

/// Every place a dab at `point` (object space) paints under the brush's symmetry: the point,
/// its mirror images in the chosen planes through the origin, and their radial copies.
std::vector<Eigen::Vector3d> symmetricPoints(const Brush& brush, const Eigen::Vector3d& point);

/// What a stroke changed: the pixels, their values before and after.
struct PixelChange {
    std::vector<std::uint32_t> pixels;
    std::vector<float> before;
    std::vector<float> after;
    bool empty() const { return pixels.empty(); }
};

/// A stroke through `points` (object space; consecutive points are joined with dabs
/// brush.spacing radii apart at most, each repeated by the brush's symmetry). Paint and erase move
/// each pixel toward the target by strength times its largest weight along the stroke (a stroke
/// never builds up over itself); smooth blends each dab toward the weighted mean of the values
/// under it. `map` is not modified.
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
    Eigen::Vector3d point;  ///< object space
    std::uint32_t triangle = 0;
    double distance = 0;  ///< along the ray (ray hits only)
};

/// Nearest hit of the ray origin + t direction, t >= 0 (object space), with either face.
std::optional<SurfaceHit> raycast(const TriangleMesh& mesh, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& direction);

/// The surface point whose mesh uv is `uv` (for painting in the UV view), if a triangle has it.
std::optional<SurfaceHit> surfaceAtUv(const TriangleMesh& mesh, const Eigen::Vector2d& uv);

}  // namespace plimsoll::editor
