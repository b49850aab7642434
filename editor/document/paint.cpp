#include "document/paint.h"

#include "plimsoll/bake.h"
#include "plimsoll/uv_layout.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace plimsoll::editor {

Result<PaintSurface> buildPaintSurface(const TriangleMesh& mesh, int width, int height) {
    if (!mesh.hasUvs()) return makeError(mesh.source + ": no UVs to paint on");
    if (width < 1 || height < 1) return makeError("painted map has no pixels");
    BakeSettings settings;
    // At least kMinTextureSize: a smaller map still gets every pixel its points.
    settings.size = std::clamp(std::max(width, height), kMinTextureSize, kMaxTextureSize);
    settings.maxTexelStretch = 0.0;  // one point per texel and island is what a brush needs
    SurfacePieceTable pieces;
    Result<SurfaceTextures> baked = bakeSurfaceTextures(mesh, settings, &pieces);
    if (!baked) return baked.error();
    const SurfaceTextures& t = *baked;
    const std::vector<std::uint32_t> islands = uvIslands(mesh);

    PaintSurface surface;
    surface.width = width;
    surface.height = height;
    surface.pixel.reserve(t.coveredCount());
    surface.position.reserve(t.coveredCount());
    surface.island.reserve(t.coveredCount());
    const double n = t.size;
    for (std::size_t i = 0; i < t.coveredCount(); ++i) {
        const std::uint32_t texel = t.texelIndex[i];
        const Eigen::Vector2d textureUv((texel % t.size + 0.5) / n, (texel / t.size + 0.5) / n);
        const Eigen::Vector2d uv = (textureUv - t.placement.offset) / t.placement.scale;
        const int x = std::clamp(static_cast<int>(std::floor(uv.x() * width)), 0, width - 1);
        const int y = std::clamp(static_cast<int>(std::floor((1.0 - uv.y()) * height)), 0,
                                 height - 1);
        surface.pixel.push_back(static_cast<std::uint32_t>(y * width + x));
        surface.position.push_back(t.position[i].cast<float>());
        const std::uint32_t triangle = pieces.pieces[pieces.firstPiece[i]].triangle;
        surface.island.push_back(islands[triangle]);
    }
    return surface;
}

double falloffWeight(Falloff falloff, double distance, double radius) {
    if (radius <= 0 || distance > radius) return 0.0;
    const double s = distance / radius;
    switch (falloff) {
        case Falloff::Constant: return 1.0;
        case Falloff::Linear: return 1.0 - s;
        case Falloff::Smooth: {
            const double a = 1.0 - s * s;
            return a * a;
        }
    }
    return 0.0;
}

namespace {

/// Dab centres along the stroke: the points, joined by dabs at most spacing apart.
std::vector<Eigen::Vector3d> dabCentres(std::span<const Eigen::Vector3d> points, double spacing,
                                        bool mirrorX) {
    std::vector<Eigen::Vector3d> dabs;
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (i > 0) {
            const Eigen::Vector3d a = points[i - 1], b = points[i];
            const int steps = spacing > 0 ? static_cast<int>(std::ceil((b - a).norm() / spacing))
                                          : 1;
            for (int k = 1; k < steps; ++k) dabs.push_back(a + (b - a) * (double(k) / steps));
        }
        dabs.push_back(points[i]);
    }
    if (mirrorX) {
        const std::size_t count = dabs.size();
        for (std::size_t i = 0; i < count; ++i) {
            dabs.emplace_back(-dabs[i].x(), dabs[i].y(), dabs[i].z());
        }
    }
    return dabs;
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

PixelChange strokeChange(const PaintedMap& map, const PaintSurface& surface, const Brush& brush,
                         std::span<const Eigen::Vector3d> points) {
    std::vector<float> values = map.values;
    if (points.empty() || brush.radius <= 0 || surface.width != map.width ||
        surface.height != map.height) {
        return {};
    }
    const std::vector<Eigen::Vector3d> dabs = dabCentres(points, brush.radius / 4, brush.mirrorX);
    const double r2 = brush.radius * brush.radius;
    const double strength = std::clamp(brush.strength, 0.0, 1.0);
    if (brush.mode == BrushMode::Smooth) {
        std::vector<std::pair<std::uint32_t, double>> under;
        for (const Eigen::Vector3d& c : dabs) {
            const Eigen::Vector3f cf = c.cast<float>();
            under.clear();
            double sum = 0, weights = 0;
            for (std::size_t i = 0; i < surface.sampleCount(); ++i) {
                const double d2 = (surface.position[i] - cf).squaredNorm();
                if (d2 > r2) continue;
                const double w = falloffWeight(brush.falloff, std::sqrt(d2), brush.radius);
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
    for (const Eigen::Vector3d& c : dabs) {
        const Eigen::Vector3f cf = c.cast<float>();
        for (std::size_t i = 0; i < surface.sampleCount(); ++i) {
            const double d2 = (surface.position[i] - cf).squaredNorm();
            if (d2 > r2) continue;
            const float w =
                static_cast<float>(falloffWeight(brush.falloff, std::sqrt(d2), brush.radius));
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
    std::vector<float> values(map.values.size(),
                              static_cast<float>(std::clamp(value, 0.0, 1.0)));
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
        const Eigen::Vector3d p = p0 + b1 * (mesh.positions[tri[1]] - p0) +
                                  b2 * (mesh.positions[tri[2]] - p0);
        return SurfaceHit{p, static_cast<std::uint32_t>(t), 0.0};
    }
    return std::nullopt;
}

}  // namespace plimsoll::editor
