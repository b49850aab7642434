#include "document/graph_view.h"
#include "plimsoll/graph_auto/graph_auto.h"

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
        case 0:
            r = v;
            g = t;
            b = p;
            break;
        case 1:
            r = q;
            g = v;
            b = p;
            break;
        case 2:
            r = p;
            g = v;
            b = t;
            break;
        case 3:
            r = p;
            g = q;
            b = v;
            break;
        case 4:
            r = t;
            g = p;
            b = v;
            break;
        default:
            r = v;
            g = p;
            b = q;
            break;
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
    for (int k = 0; k < 3; ++k)
        p[k] = static_cast<std::uint8_t>(std::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
    p[3] = 255;
}

}  // namespace

OverlayImage feedOverlay(const WaterGraph& graph, const SurfaceTextures& textures) {
    OverlayImage image = blankTexture(textures);
    const std::vector<std::int32_t> feeds = texelNodeMap(graph, textures);
    for (std::size_t i = 0; i < feeds.size(); ++i) {
        if (feeds[i] >= 0)
            put(image, textures.texelIndex[i], nodeColour(static_cast<std::size_t>(feeds[i])));
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
        centroid[t] =
            (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.0;
        lo = lo.cwiseMin(centroid[t]);
        hi = hi.cwiseMax(centroid[t]);
    }
    std::vector<int> segment(textures.coveredCount(), -1);
    if (count == 0) return segment;
    const double extent = std::max((hi - lo).maxCoeff(), 1e-9);
    const int cells = std::clamp(static_cast<int>(std::cbrt(static_cast<double>(count))), 1, 64);
    const double cell = extent / cells * (1 + 1e-9);
    auto key = [&](int x, int y, int z) {
        return (static_cast<long long>(x) * 4096 + y) * 4096 + z;
    };
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
                        if (std::max(
                                {std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != r)
                            continue;
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
        if (texelSegment[i] >= 0)
            put(image, textures.texelIndex[i],
                nodeColour(static_cast<std::size_t>(texelSegment[i])));
    }
    return image;
}

SchematicFrame schematicFrame(const WaterGraph& graph, float width, float height,
                              const Eigen::Vector2f& box) {
    SchematicFrame frame;
    const Eigen::Vector2f min(0.5f * box.x(), 0.5f * box.y());
    const Eigen::Vector2f max(std::max(min.x(), width - 0.5f * box.x()),
                              std::max(min.y(), height - 0.5f * box.y()));
    frame.pixel = 0.5f * (min + max);
    if (graph.nodes.empty()) return frame;
    // The side view looks across the hull's length: along object x or z, whichever the nodes
    // spread over more (hulls are modelled either way; with x alone, a boat built along z had
    // all its tanks at one place, pushed apart out of order).
    double xLo = std::numeric_limits<double>::max(), xHi = -xLo, zLo = xLo, zHi = -xLo;
    for (const GraphNode& node : graph.nodes) {
        xLo = std::min(xLo, node.position.x());
        xHi = std::max(xHi, node.position.x());
        zLo = std::min(zLo, node.position.z());
        zHi = std::max(zHi, node.position.z());
    }
    frame.along = zHi - zLo > xHi - xLo ? 2 : 0;
    // The profile's extent, mapped onto the canvas inside half a box of margin.
    Eigen::Vector2d lo(std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
    Eigen::Vector2d hi = -lo;
    for (const GraphNode& node : graph.nodes) {
        const Eigen::Vector2d p(node.position[frame.along], node.position.y());
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    // Metres per pixel of the mapping (before the boxes are pushed apart).
    const auto scale = [](double range, float pixels) {
        return range > 1e-12 && pixels > 0 ? static_cast<float>(range / pixels) : 0.0f;
    };
    float across = scale(hi.x() - lo.x(), max.x() - min.x());
    float up = scale(hi.y() - lo.y(), max.y() - min.y());
    if (across == 0) across = up;
    if (up == 0) up = across;
    if (across > 0) frame.metresPerPixel = {across, up};
    // The extent's centre at the canvas's: an axis the nodes do not spread along is centred.
    frame.profile = 0.5 * (lo + hi);
    return frame;
}

SchematicLayout schematicLayout(const WaterGraph& graph, float width, float height,
                                const Eigen::Vector2f& box) {
    return schematicLayout(graph, schematicFrame(graph, width, height, box), box);
}

SchematicLayout schematicLayout(const WaterGraph& graph, const SchematicFrame& frame,
                                const Eigen::Vector2f& box) {
    SchematicLayout layout;
    layout.box = box;
    layout.along = frame.along;
    layout.metresPerPixel = frame.metresPerPixel;
    const std::size_t n = graph.nodes.size();
    if (n == 0) return layout;
    for (const GraphNode& node : graph.nodes) {
        // y up in the body, down on the canvas.
        const Eigen::Vector2d d =
            Eigen::Vector2d(node.position[frame.along], node.position.y()) - frame.profile;
        layout.centre.emplace_back(
            frame.pixel.x() + static_cast<float>(d.x() / frame.metresPerPixel.x()),
            frame.pixel.y() - static_cast<float>(d.y() / frame.metresPerPixel.y()));
    }
    // Overlapping boxes pushed apart along the axis they overlap least on, half each way,
    // the lower index to the left or top where they coincide; a few sweeps settle a graph of
    // tanks (the canvas is not a bound while pushing: a crowded profile grows past it).
    const float gap = 4.0f;
    const Eigen::Vector2f need = box + Eigen::Vector2f(gap, gap);
    for (int sweep = 0; sweep < 200; ++sweep) {
        bool moved = false;
        for (std::size_t i = 0; i < n; ++i) {
            for (std::size_t j = i + 1; j < n; ++j) {
                Eigen::Vector2f d = layout.centre[j] - layout.centre[i];
                const Eigen::Vector2f overlap(need.x() - std::abs(d.x()),
                                              need.y() - std::abs(d.y()));
                if (overlap.x() <= 0 || overlap.y() <= 0) continue;
                const int axis = overlap.x() / need.x() <= overlap.y() / need.y() ? 0 : 1;
                const float sign = d[axis] > 0 ? 1.0f : d[axis] < 0 ? -1.0f : 1.0f;
                const float push = 0.5f * overlap[axis] + 0.01f;
                layout.centre[i][axis] -= sign * push;
                layout.centre[j][axis] += sign * push;
                moved = true;
            }
        }
        if (!moved) break;
    }
    return layout;
}

const std::string& schematicLabel(const GraphNode& node) {
    return node.name.empty() ? node.id : node.name;
}

Eigen::Vector2f schematicBoxFor(const WaterGraph& graph,
                                const std::function<Eigen::Vector2f(const std::string&)>& textSize,
                                const Eigen::Vector2f& minimum) {
    Eigen::Vector2f box = minimum;
    for (const GraphNode& node : graph.nodes)
        box = box.cwiseMax(textSize(schematicLabel(node)) + 2 * kSchematicMargin);
    return box;
}

Eigen::Vector3d schematicDragOffset(const SchematicLayout& layout, const Eigen::Vector2f& pixels) {
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    offset[layout.along] = double(pixels.x()) * layout.metresPerPixel.x();
    offset.y() = -double(pixels.y()) * layout.metresPerPixel.y();  // the canvas's y is down
    return offset;
}

int schematicPortAt(const SchematicLayout& layout, const Eigen::Vector2f& p, float radius) {
    for (std::size_t k = layout.centre.size(); k-- > 0;) {
        const Eigen::Vector2f port = layout.centre[k] + Eigen::Vector2f(0.5f * layout.box.x(), 0);
        if ((p - port).norm() <= radius) return static_cast<int>(k);
    }
    return -1;
}

int schematicNodeAt(const SchematicLayout& layout, const Eigen::Vector2f& p) {
    for (std::size_t k = layout.centre.size(); k-- > 0;) {
        const Eigen::Vector2f d = (p - layout.centre[k]).cwiseAbs();
        if (d.x() <= 0.5f * layout.box.x() && d.y() <= 0.5f * layout.box.y())
            return static_cast<int>(k);
    }
    return -1;
}

}  // namespace plimsoll::editor
