#include "document/overlay.h"

#include "plimsoll/graph/graph.h"

#include <cstdio>

#include <algorithm>
#include <cmath>

namespace plimsoll::editor {

const char* overlayName(Overlay overlay) {
    switch (overlay) {
        case Overlay::None:
            return "none";
        case Overlay::Permeability:
            return "permeability";
        case Overlay::Density:
            return "density";
        case Overlay::Thickness:
            return "thickness";
        case Overlay::Coverage:
            return "coverage";
        case Overlay::Position:
            return "position";
        case Overlay::AreaVector:
            return "area";
    }
    return "?";
}

std::optional<Overlay> parseOverlay(const std::string& name) {
    for (Overlay o : kOverlays) {
        if (name == overlayName(o)) return o;
    }
    return std::nullopt;
}

std::optional<MapChannel> overlayChannel(Overlay overlay) {
    switch (overlay) {
        case Overlay::Permeability:
            return MapChannel::Permeability;
        case Overlay::Density:
            return MapChannel::Density;
        case Overlay::Thickness:
            return MapChannel::Thickness;
        default:
            return std::nullopt;
    }
}

Eigen::Vector3f rampColour(double value) {
    const float t = static_cast<float>(std::clamp(value, 0.0, 1.0));
    const Eigen::Vector3f low(0.10f, 0.25f, 0.90f), high(0.95f, 0.45f, 0.05f);
    return low + (high - low) * t;
}

namespace {

std::uint8_t byte(double v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
}

void put(OverlayImage& image, std::size_t pixel, const Eigen::Vector3f& c, double alpha = 1.0) {
    image.rgba[4 * pixel + 0] = byte(c.x());
    image.rgba[4 * pixel + 1] = byte(c.y());
    image.rgba[4 * pixel + 2] = byte(c.z());
    image.rgba[4 * pixel + 3] = byte(alpha);
}

}  // namespace

OverlayImage overlayOfMap(const PaintedMap& mapRef) {
    OverlayImage image;
    const PaintedMap* map = &mapRef;
    {
        image.width = map->width;
        image.height = map->height;
        image.rgba.assign(static_cast<std::size_t>(image.width) * image.height * 4, 0);
        for (int y = 0; y < map->height; ++y) {
            const int row = map->height - 1 - y;  // map row 0 is v = 1
            for (int x = 0; x < map->width; ++x) {
                put(image, static_cast<std::size_t>(row) * image.width + x,
                    rampColour(map->values[static_cast<std::size_t>(y) * map->width + x]));
            }
        }
    }
    return image;
}

Result<OverlayImage> buildOverlay(Document& document, std::size_t body, Overlay overlay) {
    if (overlayChannel(overlay) || overlay == Overlay::None)
        return buildMapOverlay(document, body, overlay);
    Result<std::shared_ptr<const SurfaceTextures>> baked = document.physicsTextures(body);
    if (!baked) return baked.error();
    return overlayOfTextures(**baked, overlay);
}

OverlayImage buildMapOverlay(const Document& document, std::size_t body, Overlay overlay) {
    OverlayImage image;
    const std::optional<MapChannel> channel = overlayChannel(overlay);
    if (!channel) return image;
    const PaintedMap* map = document.map(body, *channel);
    if (!map) {
        image.width = image.height = 1;
        image.rgba.assign(4, 0);
        put(image, 0, rampColour(*channel == MapChannel::Permeability ? 0.0 : 1.0));
        return image;
    }
    return overlayOfMap(*map);
}

OverlayImage overlayOfTextures(const SurfaceTextures& t, Overlay overlay) {
    OverlayImage image;
    if (overlay == Overlay::None || overlayChannel(overlay)) return image;
    image.width = image.height = t.size;
    image.placement = t.placement;
    image.rgba.assign(static_cast<std::size_t>(t.size) * t.size * 4, 0);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const Eigen::Vector3d& p : t.position) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const Eigen::Vector3d extent = (hi - lo).cwiseMax(Eigen::Vector3d::Constant(1e-12));
    std::vector<double> coverage(static_cast<std::size_t>(t.size) * t.size, 0.0);
    for (std::size_t i = 0; i < t.coveredCount(); ++i) coverage[t.texelIndex[i]] += t.coverage[i];
    for (std::size_t i = 0; i < t.coveredCount(); ++i) {
        const std::uint32_t texel = t.texelIndex[i];
        switch (overlay) {
            case Overlay::Coverage:
                put(image, texel, rampColour(coverage[texel]));
                break;
            case Overlay::Position:
                put(image, texel, ((t.position[i] - lo).cwiseQuotient(extent)).cast<float>());
                break;
            case Overlay::AreaVector: {
                const double norm = t.areaVector[i].norm();
                const Eigen::Vector3d n =
                    norm > 0 ? Eigen::Vector3d(t.areaVector[i] / norm) : Eigen::Vector3d::Zero();
                put(image, texel, (n * 0.5 + Eigen::Vector3d::Constant(0.5)).cast<float>());
                break;
            }
            default:
                break;
        }
    }
    return image;
}

OverlayLegend overlayLegend(Overlay overlay, const BodyDesc* body) {
    OverlayLegend legend;
    legend.ramp = true;
    legend.low = "0";
    legend.high = "1";
    switch (overlay) {
        case Overlay::None:
            return OverlayLegend{};
        case Overlay::Permeability:
            legend.meaning = "permeability: share of the water in contact that flows in";
            break;
        case Overlay::Density: {
            const std::optional<double> shell =
                body ? body->material.shellSurfaceDensity : std::nullopt;
            char high[48];
            if (shell) std::snprintf(high, sizeof high, "%.4g kg/m^2", *shell);
            legend.high = shell ? high : "1 x shell (no shell set)";
            legend.low = "0 kg/m^2";
            legend.meaning = "shell surface density (white: the material's shell)";
            break;
        }
        case Overlay::Thickness:
            legend.high = "1 x shell thickness";
            legend.meaning = "relative shell thickness (scales the surface density)";
            break;
        case Overlay::Coverage:
            legend.meaning = "coverage: share of each physics texel covered by the surface";
            break;
        case Overlay::Position:
            legend = OverlayLegend{};
            legend.meaning = "position: red, green, blue = x, y, z across the body's bounds";
            break;
        case Overlay::AreaVector:
            legend = OverlayLegend{};
            legend.meaning = "area vector: red, green, blue = normal x, y, z (0.5 + n / 2)";
            break;
    }
    return legend;
}

Eigen::Vector2f overlayPlace(const Eigen::AlignedBox2f& view, const Eigen::Vector2f& size,
                             std::span<const Eigen::AlignedBox2f> avoid, ViewCorner corner,
                             float topMargin) {
    constexpr float kInset = 10, kGap = 6;
    const bool left = corner == ViewCorner::LowerLeft;
    auto clear = [&](const Eigen::Vector2f& at) {
        const Eigen::AlignedBox2f label(at, at + size);
        if (at.y() < view.min().y() + topMargin || at.x() < view.min().x() ||
            label.max().x() > view.max().x())
            return false;
        for (const Eigen::AlignedBox2f& box : avoid)
            if (!box.isEmpty() && box.intersects(label)) return false;
        return true;
    };
    const Eigen::Vector2f home(left ? view.min().x() + kInset : view.max().x() - kInset - size.x(),
                               view.max().y() - kInset - size.y());
    if (clear(home)) return home;
    for (const Eigen::AlignedBox2f& box : avoid) {
        if (box.isEmpty()) continue;
        const Eigen::Vector2f above(home.x(), box.min().y() - kGap - size.y());
        if (clear(above)) return above;
        // Beside it, away from the corner's side of the view.
        const Eigen::Vector2f beside(left ? box.max().x() + kGap : box.min().x() - kGap - size.x(),
                                     home.y());
        if (clear(beside)) return beside;
    }
    return home;
}

std::string surfacePointPhysics(const Document& document, std::size_t body,
                                const Eigen::Vector3d& object, double time) {
    const Project& project = document.project();
    const Eigen::Vector3d p = document.bodyPose(body).apply(object);
    const double depth = project.water.height(p.x(), p.z(), time) - p.y();
    char line[160];
    if (depth > 0) {
        const double pascals = project.medium.density * project.simulation.gravity.norm() * depth;
        std::snprintf(line, sizeof line, "submerged %.3f m: %.2f kPa", depth, pascals / 1000.0);
    } else {
        std::snprintf(line, sizeof line, "dry: %.3f m above the %s", -depth,
                      project.medium.name.c_str());
    }
    std::string out = line;
    if (const WaterGraph* graph = document.graph(body)) {
        if (const int node = nearestNode(*graph, object); node >= 0) {
            const GraphNode& n = graph->nodes[static_cast<std::size_t>(node)];
            out +=
                "\nfeeds " + n.id + (n.name.empty() || n.name == n.id ? "" : " (" + n.name + ")");
        }
    }
    return out;
}

}  // namespace plimsoll::editor
