#include "document/paint.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/io/painted_map_io.h"
#include "plimsoll/geometry/uv_layout.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

namespace plimsoll::editor {

namespace {

/// The map's pixel grid, reached over every UV the mesh has: the mesh's UVs affinely moved so
/// that texel (i, j) of a bake of `size` texels a side is exactly pixel column x0 + i and
/// pixel row (from the bottom, v up) y0 + j of the map. A UV outside 0..1 lands on a texel
/// beyond the map's edge, whose pixel is the edge one (PaintedMap::sample clamps the same way).
struct PixelGrid {
    int x0 = 0, y0 = 0;
    int size = 0;
    TriangleMesh mesh;  ///< the mesh with its UVs in the grid's texture space, all within 0..1
};

/// One pixel of margin on every side keeps the moved UVs strictly inside 0..1, so the bake
/// places them as they are (identity placement) instead of fitting them into its square.
PixelGrid pixelGrid(const TriangleMesh& mesh, int width, int height) {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
    Eigen::Vector2d hi = -lo;
    for (const Eigen::Vector2d& uv : mesh.uvs) {
        lo = lo.cwiseMin(uv);
        hi = hi.cwiseMax(uv);
    }
    PixelGrid grid;
    grid.x0 = static_cast<int>(std::floor(lo.x() * width)) - 1;
    grid.y0 = static_cast<int>(std::floor(lo.y() * height)) - 1;
    const int x1 = static_cast<int>(std::ceil(hi.x() * width)) + 1;
    const int y1 = static_cast<int>(std::ceil(hi.y() * height)) + 1;
    grid.size = std::max({x1 - grid.x0, y1 - grid.y0, kMinTextureSize});
    grid.mesh = mesh;
    const double n = grid.size;
    for (Eigen::Vector2d& uv : grid.mesh.uvs) {
        uv = Eigen::Vector2d((uv.x() * width - grid.x0) / n, (uv.y() * height - grid.y0) / n);
    }
    return grid;
}

/// Half a pixel's sides on each triangle's surface (PaintSurface::halfU, halfV).
struct PixelSides {
    Eigen::Vector3f u = Eigen::Vector3f::Zero();
    Eigen::Vector3f v = Eigen::Vector3f::Zero();
};

std::vector<PixelSides> pixelSides(const TriangleMesh& mesh, int width, int height) {
    std::vector<PixelSides> out(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Eigen::Vector2d a = mesh.uvs[tri[0]], b = mesh.uvs[tri[1]], c = mesh.uvs[tri[2]];
        const Eigen::Vector3d p0 = mesh.positions[tri[0]];
        const Eigen::Vector3d e1 = mesh.positions[tri[1]] - p0, e2 = mesh.positions[tri[2]] - p0;
        const double longest = std::max({e1.norm(), e2.norm(), (e2 - e1).norm()});
        const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
        if (!(std::abs(det) > 0)) continue;
        // d position / d u and d position / d v on the triangle's plane.
        Eigen::Vector3d du = (e1 * (c - a).y() - e2 * (b - a).y()) / det / (2.0 * width);
        Eigen::Vector3d dv = (e2 * (b - a).x() - e1 * (c - a).x()) / det / (2.0 * height);
        // A sliver in UV stretches a pixel without bound; its piece stays on the triangle.
        if (du.norm() > longest) du *= longest / du.norm();
        if (dv.norm() > longest) dv *= longest / dv.norm();
        if (du.allFinite() && dv.allFinite()) out[t] = {du.cast<float>(), dv.cast<float>()};
    }
    return out;
}

}  // namespace

Result<PaintSurface> buildPaintSurface(const TriangleMesh& mesh, int width, int height) {
    if (!mesh.hasUvs())
        return makeError(ErrorKind::invalidArgument, mesh.source + ": no UVs to paint on");
    if (width < 1 || height < 1)
        return makeError(ErrorKind::invalidArgument, "painted map has no pixels");
    // The bake runs on the map's own pixel grid: each texel is one pixel, so every pixel the
    // surface covers gets its points. (A bake of the UVs fitted into its square, as the
    // physics bakes them, puts its texel centres on a grid a little coarser than the pixels
    // when the UVs reach outside 0..1, and skips one pixel column and row in every few dozen.)
    const PixelGrid grid = pixelGrid(mesh, width, height);
    if (grid.size > kMaxTextureSize) {
        return makeError(ErrorKind::limit,
                         mesh.source + ": its UVs span " + std::to_string(grid.size) +
                             " pixels of a " + std::to_string(width) + " x " +
                             std::to_string(height) + " map, more than the " +
                             std::to_string(kMaxTextureSize) +
                             " a paint surface bakes (kMaxTextureSize, limits.h)");
    }
    BakeSettings settings;
    settings.size = grid.size;
    settings.maxTexelStretch = 0.0;  // one point per texel and island is what a brush needs
    SurfacePieceTable pieces;
    Result<SurfaceTextures> baked = bakeSurfaceTextures(grid.mesh, settings, &pieces);
    if (!baked) return baked.error();
    const SurfaceTextures& t = *baked;
    if (!t.placement.isIdentity()) {
        return makeError(ErrorKind::invalidArgument,
                         mesh.source + ": its UVs could not be laid on the map's pixels");
    }
    const std::vector<std::uint32_t> islands = uvIslands(mesh);
    const std::vector<PixelSides> sides = pixelSides(mesh, width, height);

    PaintSurface surface;
    surface.width = width;
    surface.height = height;
    surface.pixel.reserve(t.coveredCount());
    surface.position.reserve(t.coveredCount());
    surface.island.reserve(t.coveredCount());
    surface.normal.reserve(t.coveredCount());
    surface.halfU.reserve(t.coveredCount());
    surface.halfV.reserve(t.coveredCount());
    for (std::size_t i = 0; i < t.coveredCount(); ++i) {
        const std::uint32_t texel = t.texelIndex[i];
        const int column = grid.x0 + static_cast<int>(texel % t.size);
        const int rowUp = grid.y0 + static_cast<int>(texel / t.size);  // from the bottom, v up
        const int x = std::clamp(column, 0, width - 1);
        const int y = std::clamp(height - 1 - rowUp, 0, height - 1);
        surface.pixel.push_back(static_cast<std::uint32_t>(y * width + x));
        surface.position.push_back(t.position[i].cast<float>());
        const std::uint32_t triangle = pieces.pieces[pieces.firstPiece[i]].triangle;
        surface.island.push_back(islands[triangle]);
        surface.halfU.push_back(sides[triangle].u);
        surface.halfV.push_back(sides[triangle].v);
        const Eigen::Vector3d& areaVector = t.areaVector[i];
        surface.normal.push_back(areaVector.norm() > 0
                                     ? Eigen::Vector3f(areaVector.normalized().cast<float>())
                                     : Eigen::Vector3f::Zero());
    }
    return surface;
}

double facingWeight(const Brush& brush, const Eigen::Vector3d& normal,
                    const Eigen::Vector3d& towardViewer) {
    const double c = normal.dot(towardViewer);
    if (brush.frontFacesOnly && c <= 0) return 0.0;
    if (!(brush.normalAngle < 180.0)) return 1.0;  // off (and NaN: off)
    const double angle = std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / std::numbers::pi;
    const double outer = std::max(brush.normalAngle, 0.0), inner = outer / 2;
    if (angle <= inner) return 1.0;
    if (angle >= outer) return 0.0;
    return (outer - angle) / (outer - inner);
}

double falloffWeight(Falloff falloff, double distance, double radius, const FalloffCurve* curve) {
    if (radius <= 0 || distance > radius) return 0.0;
    const double s = distance / radius;
    const double p = 1.0 - s;
    switch (falloff) {
        case Falloff::Custom:
            return curve ? (*curve)(s) : FalloffCurve{}(s);
        case Falloff::Constant:
            return 1.0;
        case Falloff::Linear:
            return p;
        case Falloff::Smooth: {
            const double a = 1.0 - s * s;
            return a * a;
        }
        case Falloff::Sphere:
            return std::sqrt(std::max(0.0, 1.0 - s * s));
        case Falloff::Root:
            return std::sqrt(p);
        case Falloff::Sharp:
            return p * p;
        case Falloff::InverseSquare:
            return p * (2.0 - p);
    }
    return 0.0;
}

double FalloffCurve::operator()(double s) const {
    if (points.empty()) return 0.0;
    if (points.size() == 1) return std::clamp(points[0].y(), 0.0, 1.0);
    s = std::clamp(s, points.front().x(), points.back().x());
    const std::size_t n = points.size();
    // The segment holding s, and the secant slopes either side of its ends.
    std::size_t k = 0;
    while (k + 2 < n && s > points[k + 1].x()) ++k;
    auto secant = [&](std::size_t i) {
        const Eigen::Vector2d d = points[i + 1] - points[i];
        return d.x() > 0 ? d.y() / d.x() : 0.0;
    };
    // Fritsch-Carlson tangents: the mean of the secants, 0 at a local extremum or flat
    // stretch, then scaled into the circle of radius 3 that keeps the segment monotone.
    auto tangent = [&](std::size_t i) {
        if (i == 0) return secant(0);
        if (i == n - 1) return secant(n - 2);
        const double a = secant(i - 1), b = secant(i);
        return a * b > 0 ? 0.5 * (a + b) : 0.0;
    };
    const double d = secant(k);
    double m0 = tangent(k), m1 = tangent(k + 1);
    if (d == 0) {
        m0 = m1 = 0;
    } else {
        const double a = m0 / d, b = m1 / d, r = a * a + b * b;
        if (r > 9) {
            const double t = 3 / std::sqrt(r);
            m0 = t * a * d;
            m1 = t * b * d;
        }
    }
    const double h = points[k + 1].x() - points[k].x();
    if (!(h > 0)) return std::clamp(points[k].y(), 0.0, 1.0);
    const double t = (s - points[k].x()) / h, t2 = t * t, t3 = t2 * t;
    const double y = (2 * t3 - 3 * t2 + 1) * points[k].y() + (t3 - 2 * t2 + t) * h * m0 +
                     (-2 * t3 + 3 * t2) * points[k + 1].y() + (t3 - t2) * h * m1;
    return std::clamp(y, 0.0, 1.0);
}

FalloffCurve FalloffCurve::preset(Falloff falloff, int count) {
    count = std::clamp(count, 2, kMaxFalloffPoints);
    FalloffCurve curve;
    curve.points.clear();
    for (int i = 0; i < count; ++i) {
        const double s = double(i) / (count - 1);
        curve.points.emplace_back(
            s, falloff == Falloff::Custom ? 1.0 - s : falloffWeight(falloff, s, 1.0));
    }
    return curve;
}

FalloffCurve FalloffCurve::sanitised(std::vector<Eigen::Vector2d> points) {
    std::erase_if(points, [](const Eigen::Vector2d& p) { return !p.allFinite(); });
    for (Eigen::Vector2d& p : points) p = p.cwiseMax(0.0).cwiseMin(1.0);
    std::stable_sort(
        points.begin(), points.end(),
        [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() < b.x(); });
    FalloffCurve curve;
    curve.points.clear();
    for (const Eigen::Vector2d& p : points) {
        if (!curve.points.empty() && p.x() - curve.points.back().x() < 0.01) continue;
        curve.points.push_back(p);
    }
    if (curve.points.empty()) return FalloffCurve{};
    if (curve.points.front().x() > 0) {
        if (curve.points.front().x() < 0.01)
            curve.points.front().x() = 0;
        else
            curve.points.insert(curve.points.begin(), Eigen::Vector2d(0, curve.points.front().y()));
    }
    if (curve.points.back().x() < 1) {
        if (curve.points.back().x() > 0.99)
            curve.points.back().x() = 1;
        else
            curve.points.emplace_back(1, curve.points.back().y());
    }
    if (curve.points.size() == 1) curve.points.emplace_back(1, curve.points[0].y());
    if (curve.points.size() > static_cast<std::size_t>(kMaxFalloffPoints)) {
        // Keep the ends and an even pick of the points between.
        std::vector<Eigen::Vector2d> kept;
        const std::size_t n = curve.points.size();
        for (int i = 0; i < kMaxFalloffPoints; ++i)
            kept.push_back(curve.points[i * (n - 1) / (kMaxFalloffPoints - 1)]);
        curve.points = std::move(kept);
    }
    return curve;
}

Eigen::Vector2d LazyMouse::follow(const Eigen::Vector2d& cursor) {
    if (!brush_) {
        brush_ = cursor;
        return *brush_;
    }
    const Eigen::Vector2d pull = cursor - *brush_;
    const double length = pull.norm();
    if (length > radius_) *brush_ += pull * ((length - radius_) / length);
    return *brush_;
}

std::vector<Eigen::Vector2d> lineSamples(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                         double step) {
    const double length = (to - from).norm();
    const int n = std::isfinite(length) && step > 0
                      ? std::clamp(static_cast<int>(std::ceil(length / step)), 1, 100000)
                      : 1;
    std::vector<Eigen::Vector2d> out;
    out.reserve(n + 1);
    for (int k = 0; k <= n; ++k) out.push_back(from + (to - from) * (double(k) / n));
    return out;
}

Status loadBrushAlpha(Brush& brush, const std::filesystem::path& path) {
    if (path.empty()) return makeError(ErrorKind::invalidArgument, "brush alpha: no file named");
    Result<PaintedMap> image = loadPaintedMap(path);
    if (!image) return withContext("brush alpha '" + path.string() + "': ", image.error());
    brush.alpha = std::make_shared<const PaintedMap>(std::move(image).value());
    brush.alphaPath = path.string();
    return Ok{};
}

double dabWeight(const Brush& brush, const Eigen::Vector3d& offset) {
    const double d = offset.norm();
    const double w = falloffWeight(brush.falloff, d, brush.radius, &brush.curve);
    if (w <= 0 || !brush.alpha || brush.alpha->values.empty()) return w;
    // The image's square over the dab, across the axis: u along one tangent, v along the other.
    const Eigen::Vector3d axis =
        brush.alphaAxis.norm() > 0 ? brush.alphaAxis.normalized() : Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d helper =
        std::abs(axis.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
    const Eigen::Vector3d across = helper.cross(axis).normalized();  // image right
    const Eigen::Vector3d up = axis.cross(across);                   // image up
    const double u = 0.5 + offset.dot(across) / (2 * brush.radius);
    const double v = 0.5 + offset.dot(up) / (2 * brush.radius);
    return w * std::clamp(brush.alpha->sample(u, v), 0.0, 1.0);
}

namespace {
constexpr const char* kFalloffNames[kFalloffCount] = {
    "smooth", "linear", "constant", "sphere", "root", "sharp", "inverse-square", "custom"};
}  // namespace

const char* falloffName(Falloff falloff) { return kFalloffNames[static_cast<int>(falloff)]; }

std::optional<Falloff> parseFalloff(const std::string& name) {
    for (int i = 0; i < kFalloffCount; ++i) {
        if (name == kFalloffNames[i]) return static_cast<Falloff>(i);
    }
    return std::nullopt;
}

std::vector<Eigen::Vector3d> symmetricPoints(const Brush& brush, const Eigen::Vector3d& point) {
    std::vector<Eigen::Vector3d> out{point};
    const bool mirrors[3] = {brush.mirrorX, brush.mirrorY, brush.mirrorZ};
    for (int axis = 0; axis < 3; ++axis) {
        if (!mirrors[axis]) continue;
        const std::size_t count = out.size();
        for (std::size_t i = 0; i < count; ++i) {
            Eigen::Vector3d m = out[i];
            m[axis] = -m[axis];
            out.push_back(m);
        }
    }
    const int copies = std::clamp(brush.radial, 1, kMaxRadialCopies);
    const std::size_t count = out.size();
    for (int k = 1; k < copies; ++k) {
        const Eigen::Matrix3d turn =
            Eigen::AngleAxisd(2.0 * std::numbers::pi * k / copies, Eigen::Vector3d::UnitY())
                .toRotationMatrix();
        for (std::size_t i = 0; i < count; ++i) out.push_back(turn * out[i]);
    }
    return out;
}

namespace {

/// Dab centres along the stroke: the points, joined by dabs at most spacing apart, each with
/// its symmetric copies.
std::vector<Eigen::Vector3d> dabCentres(std::span<const Eigen::Vector3d> points, double spacing,
                                        const Brush& brush) {
    std::vector<Eigen::Vector3d> dabs;
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (i > 0) {
            const Eigen::Vector3d a = points[i - 1], b = points[i];
            const int steps =
                spacing > 0 ? static_cast<int>(std::ceil((b - a).norm() / spacing)) : 1;
            for (int k = 1; k < steps; ++k) dabs.push_back(a + (b - a) * (double(k) / steps));
        }
        dabs.push_back(points[i]);
    }
    std::vector<Eigen::Vector3d> all;
    for (const Eigen::Vector3d& dab : dabs) {
        for (const Eigen::Vector3d& p : symmetricPoints(brush, dab)) all.push_back(p);
    }
    return all;
}

PixelChange changeFrom(const PaintedMap& map, const std::vector<float>& values) {
    PixelChange change;
    for (std::size_t p = 0; p < values.size(); ++p) {
        if (values[p] != map.values[p]) {
            change.pixels.push_back(static_cast<std::uint32_t>(p));
            change.before.push_back(map.values[p]);
            change.after.push_back(values[p]);
        }
    }
    return change;
}

}  // namespace

namespace {

/// Which samples a viewer sees: the surface's samples dropped into a grid across the view,
/// each cell keeping its nearest depth; a sample more than two cells behind its cell's nearest
/// is hidden (two cells: a surface turned up to 63 degrees from the view still sees itself
/// within one cell). `view` (unit) points toward the viewer. Orthographic (no `eye`): cells
/// `cell` wide across the view. Perspective: cells of the angle `cell` spans at `reference`
/// (the stroke's first dab), so `cell` wide there and wider further away; samples behind the
/// eye are hidden.
std::vector<bool> visibleSamples(const PaintSurface& surface, const Eigen::Vector3d& view,
                                 double cell, const std::optional<Eigen::Vector3d>& eye,
                                 const Eigen::Vector3d& reference) {
    const Eigen::Vector3d helper =
        std::abs(view.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
    const Eigen::Vector3d u = helper.cross(view).normalized(), v = view.cross(u);
    const std::size_t count = surface.sampleCount();
    // Each sample's place across the view (in cells) and its depth toward the viewer (larger:
    // nearer; in perspective minus its distance along the view axis).
    std::vector<Eigen::Vector2d> across(count);
    std::vector<double> depth(count);
    std::vector<bool> visible(count, true);
    const double referenceDistance = eye ? std::max((*eye - reference).dot(view), cell) : 1.0;
    for (std::size_t i = 0; i < count; ++i) {
        const Eigen::Vector3d p = surface.position[i].cast<double>();
        if (!eye) {
            across[i] = {p.dot(u) / cell, p.dot(v) / cell};
            depth[i] = p.dot(view);
            continue;
        }
        const Eigen::Vector3d d = p - *eye;
        const double distance = -d.dot(view);  // along the view axis, in front of the eye
        if (!(distance > 1e-9 * referenceDistance)) {
            visible[i] = false;
            continue;
        }
        across[i] = Eigen::Vector2d(d.dot(u), d.dot(v)) * (referenceDistance / (distance * cell));
        depth[i] = -distance;
    }
    // Two cells deep at the sample: in perspective a cell widens with the distance.
    auto slack = [&](std::size_t i) {
        return 2 * cell * (eye ? -depth[i] / referenceDistance : 1.0);
    };
    auto key = [&](std::size_t i) {
        const auto a = static_cast<std::int64_t>(std::floor(across[i].x()));
        const auto b = static_cast<std::int64_t>(std::floor(across[i].y()));
        return (a << 32) ^ (b & 0xffffffff);
    };
    std::unordered_map<std::int64_t, double> nearest;
    for (std::size_t i = 0; i < count; ++i) {
        if (!visible[i]) continue;
        auto [it, added] = nearest.try_emplace(key(i), depth[i]);
        if (!added) it->second = std::max(it->second, depth[i]);
    }
    for (std::size_t i = 0; i < count; ++i) {
        if (visible[i]) visible[i] = depth[i] >= nearest[key(i)] - slack(i);
    }
    return visible;
}

}  // namespace

namespace {

/// From the dab centre `c` to the nearest point of sample i's pixel (its parallelogram
/// position +- halfU +- halfV): the brush paints the pixel by how close it comes to any of it,
/// so a stroke between two pixels' centres paints them both. Null when even the parallelogram's
/// far corner is beyond `radius`.
std::optional<Eigen::Vector3d> reachOffset(const PaintSurface& surface, std::size_t i,
                                           const Eigen::Vector3f& c, double radius) {
    const Eigen::Vector3f o = surface.position[i] - c;
    if (surface.halfU.size() != surface.sampleCount()) {
        if (o.squaredNorm() > radius * radius) return std::nullopt;
        return o.cast<double>();
    }
    const Eigen::Vector3f& a = surface.halfU[i];
    const Eigen::Vector3f& b = surface.halfV[i];
    const double reach = radius + a.norm() + b.norm();
    if (o.squaredNorm() > reach * reach) return std::nullopt;
    // The parallelogram's point nearest the centre: minimise |o + alpha a + beta b| over
    // alpha, beta in [-1, 1] (the plane's solution, clamped, then each refined with the other
    // held: exact for a rectangle and within a hair of it for the skewed pixels of a UV map).
    const double aa = a.squaredNorm(), bb = b.squaredNorm(), ab = a.dot(b);
    const double ao = a.dot(o), bo = b.dot(o);
    const double det = aa * bb - ab * ab;
    double alpha = 0, beta = 0;
    if (det > 1e-12 * aa * bb) {
        alpha = std::clamp((ab * bo - bb * ao) / det, -1.0, 1.0);
        beta = std::clamp((ab * ao - aa * bo) / det, -1.0, 1.0);
    }
    if (aa > 0) alpha = std::clamp(-(ao + beta * ab) / aa, -1.0, 1.0);
    if (bb > 0) beta = std::clamp(-(bo + alpha * ab) / bb, -1.0, 1.0);
    const Eigen::Vector3d offset =
        o.cast<double>() + alpha * a.cast<double>() + beta * b.cast<double>();
    if (offset.squaredNorm() > radius * radius) return std::nullopt;
    return offset;
}

}  // namespace

PixelChange strokeChange(const PaintedMap& map, const PaintSurface& surface, const Brush& brush,
                         std::span<const Eigen::Vector3d> points) {
    std::vector<float> values = map.values;
    if (points.empty() || brush.radius <= 0 || surface.width != map.width ||
        surface.height != map.height) {
        return {};
    }
    // A spacing of 0 (or garbage) would be no spacing at all: the quarter radius then.
    const double spacing = std::isfinite(brush.spacing) && brush.spacing > 0 ? brush.spacing : 0.25;
    const std::vector<Eigen::Vector3d> dabs = dabCentres(points, brush.radius * spacing, brush);
    // Each dab's direction toward the viewer: the symmetric copies are linear maps (mirrors
    // and turns about y) applied in the same order to every stroke point, so the same copies
    // of the view direction go with them (a mirrored dab on the far side faces a mirrored
    // viewer, as in Blender).
    const bool facing = brush.frontFacesOnly || brush.normalAngle < 180.0;
    const Eigen::Vector3d view =
        brush.alphaAxis.norm() > 0 ? brush.alphaAxis.normalized() : Eigen::Vector3d::UnitZ();
    const std::vector<Eigen::Vector3d> views = symmetricPoints(brush, view);
    std::vector<std::optional<Eigen::Vector3d>> eyes(views.size());
    if (brush.eye && brush.eye->allFinite()) {
        const std::vector<Eigen::Vector3d> mirrored = symmetricPoints(brush, *brush.eye);
        std::copy(mirrored.begin(), mirrored.end(), eyes.begin());
    }
    // Occlusion: one visibility per symmetric view, for the whole stroke.
    std::vector<std::vector<bool>> visible;
    if (brush.occlusion) {
        for (std::size_t c = 0; c < views.size(); ++c) {
            visible.push_back(
                visibleSamples(surface, views[c].normalized(), brush.radius / 4, eyes[c], dabs[c]));
        }
    }
    auto facingOf = [&](std::size_t dab, std::size_t sample) {
        const std::size_t copy = dab % views.size();
        if (!visible.empty() && !visible[copy][sample]) return 0.0;
        if (!facing || sample >= surface.normal.size()) return 1.0;
        Eigen::Vector3d toward = views[copy];
        if (eyes[copy]) {
            toward = *eyes[copy] - surface.position[sample].cast<double>();
            if (toward.norm() <= 0) return 0.0;
            toward.normalize();
        }
        return facingWeight(brush, surface.normal[sample].cast<double>(), toward);
    };
    const double strength = std::clamp(brush.strength, 0.0, 1.0);
    if (brush.mode == BrushMode::Smooth) {
        std::vector<std::pair<std::uint32_t, double>> under;
        for (std::size_t k = 0; k < dabs.size(); ++k) {
            const Eigen::Vector3f cf = dabs[k].cast<float>();
            under.clear();
            double sum = 0, weights = 0;
            for (std::size_t i = 0; i < surface.sampleCount(); ++i) {
                const std::optional<Eigen::Vector3d> offset =
                    reachOffset(surface, i, cf, brush.radius);
                if (!offset) continue;
                const double w = dabWeight(brush, *offset) * facingOf(k, i);
                if (w <= 0) continue;
                under.emplace_back(surface.pixel[i], w);
                sum += w * values[surface.pixel[i]];
                weights += w;
            }
            if (weights <= 0) continue;
            const double mean = sum / weights;
            for (auto [p, w] : under) {
                values[p] = static_cast<float>(values[p] + (mean - values[p]) * strength * w);
            }
        }
        return changeFrom(map, values);
    }
    // Paint / erase: the largest weight each pixel sees along the stroke.
    std::vector<float> weight(values.size(), 0.0f);
    for (std::size_t k = 0; k < dabs.size(); ++k) {
        const Eigen::Vector3f cf = dabs[k].cast<float>();
        for (std::size_t i = 0; i < surface.sampleCount(); ++i) {
            const std::optional<Eigen::Vector3d> offset = reachOffset(surface, i, cf, brush.radius);
            if (!offset) continue;
            const float w = static_cast<float>(dabWeight(brush, *offset) * facingOf(k, i));
            float& slot = weight[surface.pixel[i]];
            slot = std::max(slot, w);
        }
    }
    const double target = brush.mode == BrushMode::Erase ? 0.0 : std::clamp(brush.value, 0.0, 1.0);
    for (std::size_t p = 0; p < values.size(); ++p) {
        if (weight[p] <= 0) continue;
        values[p] = static_cast<float>(values[p] + (target - values[p]) * strength * weight[p]);
    }
    return changeFrom(map, values);
}

namespace {

std::optional<std::size_t> nearestSample(const PaintSurface& surface, const Eigen::Vector3d& p) {
    const Eigen::Vector3f pf = p.cast<float>();
    std::optional<std::size_t> best;
    float bestD2 = std::numeric_limits<float>::max();
    for (std::size_t i = 0; i < surface.sampleCount(); ++i) {
        const float d2 = (surface.position[i] - pf).squaredNorm();
        if (d2 < bestD2) {
            bestD2 = d2;
            best = i;
        }
    }
    return best;
}

}  // namespace

PixelChange fillIslandChange(const PaintedMap& map, const PaintSurface& surface,
                             const Eigen::Vector3d& point, double value, bool mirrorX) {
    std::vector<float> values = map.values;
    if (surface.width != map.width || surface.height != map.height) return {};
    std::vector<Eigen::Vector3d> centres{point};
    if (mirrorX) centres.emplace_back(-point.x(), point.y(), point.z());
    const float v = static_cast<float>(std::clamp(value, 0.0, 1.0));
    for (const Eigen::Vector3d& c : centres) {
        const std::optional<std::size_t> nearest = nearestSample(surface, c);
        if (!nearest) continue;
        const std::uint32_t island = surface.island[*nearest];
        for (std::size_t i = 0; i < surface.sampleCount(); ++i) {
            if (surface.island[i] == island) values[surface.pixel[i]] = v;
        }
    }
    return changeFrom(map, values);
}

PixelChange fillAllChange(const PaintedMap& map, double value) {
    std::vector<float> values(map.values.size(), static_cast<float>(std::clamp(value, 0.0, 1.0)));
    return changeFrom(map, values);
}

std::optional<double> pickValue(const PaintedMap& map, const PaintSurface& surface,
                                const Eigen::Vector3d& point) {
    if (surface.width != map.width || surface.height != map.height) return std::nullopt;
    const std::optional<std::size_t> nearest = nearestSample(surface, point);
    if (!nearest) return std::nullopt;
    return map.values[surface.pixel[*nearest]];
}

void applyValues(PaintedMap& map, const std::vector<std::uint32_t>& pixels,
                 const std::vector<float>& values) {
    for (std::size_t i = 0; i < pixels.size(); ++i) map.values[pixels[i]] = values[i];
}

std::optional<SurfaceHit> raycast(const TriangleMesh& mesh, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& direction) {
    std::optional<SurfaceHit> best;
    const Eigen::Vector3d d = direction.normalized();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Eigen::Vector3d& p0 = mesh.positions[tri[0]];
        const Eigen::Vector3d e1 = mesh.positions[tri[1]] - p0;
        const Eigen::Vector3d e2 = mesh.positions[tri[2]] - p0;
        // Moller-Trumbore.
        const Eigen::Vector3d pv = d.cross(e2);
        const double det = e1.dot(pv);
        if (std::abs(det) < 1e-14) continue;
        const double inv = 1.0 / det;
        const Eigen::Vector3d tv = origin - p0;
        const double u = tv.dot(pv) * inv;
        if (u < 0 || u > 1) continue;
        const Eigen::Vector3d qv = tv.cross(e1);
        const double v = d.dot(qv) * inv;
        if (v < 0 || u + v > 1) continue;
        const double dist = e2.dot(qv) * inv;
        if (dist < 0 || (best && dist >= best->distance)) continue;
        best = SurfaceHit{origin + dist * d, static_cast<std::uint32_t>(t), dist};
    }
    return best;
}

std::optional<SurfaceHit> surfaceAtUv(const TriangleMesh& mesh, const Eigen::Vector2d& uv) {
    if (!mesh.hasUvs()) return std::nullopt;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Eigen::Vector2d a = mesh.uvs[tri[0]], b = mesh.uvs[tri[1]], c = mesh.uvs[tri[2]];
        const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
        if (std::abs(det) < 1e-18) continue;
        const Eigen::Vector2d q = uv - a;
        const double b1 = (q.x() * (c - a).y() - q.y() * (c - a).x()) / det;
        const double b2 = ((b - a).x() * q.y() - (b - a).y() * q.x()) / det;
        if (b1 < -1e-9 || b2 < -1e-9 || b1 + b2 > 1 + 1e-9) continue;
        const Eigen::Vector3d& p0 = mesh.positions[tri[0]];
        const Eigen::Vector3d p =
            p0 + b1 * (mesh.positions[tri[1]] - p0) + b2 * (mesh.positions[tri[2]] - p0);
        return SurfaceHit{p, static_cast<std::uint32_t>(t), 0.0};
    }
    return std::nullopt;
}

}  // namespace plimsoll::editor
