#include "document/graph_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace plimsoll::editor {

Eigen::Vector3f nodeColour(std::size_t i) {
    // HSV with the golden-angle hue step: neighbours in index get far-apart hues.
    const double h = std::fmod(0.08 + 0.6180339887498949 * static_cast<double>(i), 1.0) * 6.0;
    const double s = 0.65, v = 0.95;
    const int sector = static_cast<int>(h) % 6;
    const double f = h - std::floor(h);
    const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    double r = v, g = t, b = p;
    switch (sector) {
        case 0: r = v; g = t; b = p; break;
        case 1: r = q; g = v; b = p; break;
        case 2: r = p; g = v; b = t; break;
        case 3: r = p; g = q; b = v; break;
        case 4: r = t; g = p; b = v; break;
        default: r = v; g = p; b = q; break;
    }
    return {float(r), float(g), float(b)};
}

namespace {

OverlayImage blankTexture(const SurfaceTextures& textures) {
    OverlayImage image;
    image.width = image.height = textures.size;
    image.placement = textures.placement;
    image.rgba.assign(static_cast<std::size_t>(textures.size) * textures.size * 4, 0);
    return image;
}

void put(OverlayImage& image, std::uint32_t texel, const Eigen::Vector3f& c) {
    std::uint8_t* p = &image.rgba[static_cast<std::size_t>(texel) * 4];
    for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
    p[3] = 255;
}

}  // namespace

OverlayImage feedOverlay(const WaterGraph& graph, const SurfaceTextures& textures) {
    OverlayImage image = blankTexture(textures);
    const std::vector<std::int32_t> feeds = texelNodeMap(graph, textures);
    for (std::size_t i = 0; i < feeds.size(); ++i) {
        if (feeds[i] >= 0) put(image, textures.texelIndex[i], nodeColour(static_cast<std::size_t>(feeds[i])));
    }
    return image;
}

std::vector<int> texelSegments(const TriangleMesh& mesh, const MeshSegmentation& segmentation,
                               const SurfaceTextures& textures,
                               const std::function<void(double)>& progress) {
    // Triangle centroids bucketed on a uniform grid; each texel searches growing shells of
    // cells until the nearest centroid found cannot be beaten by a farther shell.
    const std::size_t count = std::min(mesh.triangles.size(), segmentation.triangleSegment.size());
    std::vector<Eigen::Vector3d> centroid(count);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (std::size_t t = 0; t < count; ++t) {
        const Triangle& tri = mesh.triangles[t];
        centroid[t] = (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.0;
        lo = lo.cwiseMin(centroid[t]);
        hi = hi.cwiseMax(centroid[t]);
    }
    std::vector<int> segment(textures.coveredCount(), -1);
    if (count == 0) return segment;
    const double extent = std::max((hi - lo).maxCoeff(), 1e-9);
    const int cells = std::clamp(static_cast<int>(std::cbrt(static_cast<double>(count))), 1, 64);
    const double cell = extent / cells * (1 + 1e-9);
    auto key = [&](int x, int y, int z) { return (static_cast<long long>(x) * 4096 + y) * 4096 + z; };
    std::unordered_map<long long, std::vector<std::uint32_t>> grid;
    auto cellOf = [&](const Eigen::Vector3d& p, int k) {
        return std::clamp(static_cast<int>(std::floor((p[k] - lo[k]) / cell)), 0, cells - 1);
    };
    for (std::size_t t = 0; t < count; ++t) {
        grid[key(cellOf(centroid[t], 0), cellOf(centroid[t], 1), cellOf(centroid[t], 2))].push_back(
            static_cast<std::uint32_t>(t));
    }
    for (std::size_t i = 0; i < textures.coveredCount(); ++i) {
        const Eigen::Vector3d& p = textures.position[i];
        const int c[3] = {cellOf(p, 0), cellOf(p, 1), cellOf(p, 2)};
        double best = std::numeric_limits<double>::max();
        std::uint32_t bestT = 0;
        for (int r = 0; r <= cells; ++r) {
            for (int x = c[0] - r; x <= c[0] + r; ++x)
                for (int y = c[1] - r; y <= c[1] + r; ++y)
                    for (int z = c[2] - r; z <= c[2] + r; ++z) {
                        if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != r) continue;
                        auto it = grid.find(key(x, y, z));
                        if (it == grid.end()) continue;
                        for (std::uint32_t t : it->second) {
                            const double d = (centroid[t] - p).squaredNorm();
                            if (d < best) best = d, bestT = t;
                        }
                    }
            // Anything in shell r + 1 is at least r cells away from p's cell.
            if (best < std::numeric_limits<double>::max() && std::sqrt(best) <= r * cell) break;
        }
        segment[i] = segmentation.triangleSegment[bestT];
        if (progress && i % 4096 == 0) progress(double(i) / textures.coveredCount());
    }
    if (progress) progress(1.0);
    return segment;
}

OverlayImage segmentOverlay(const std::vector<int>& texelSegment, const SurfaceTextures& textures) {
    OverlayImage image = blankTexture(textures);
    for (std::size_t i = 0; i < texelSegment.size() && i < textures.coveredCount(); ++i) {
        if (texelSegment[i] >= 0) put(image, textures.texelIndex[i], nodeColour(static_cast<std::size_t>(texelSegment[i])));
    }
    return image;
}

}  // namespace plimsoll::editor
