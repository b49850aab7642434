#include "document/overlay.h"

#include <algorithm>
#include <cmath>

namespace plimsoll::editor {

const char* overlayName(Overlay overlay) {
    switch (overlay) {
        case Overlay::None: return "none";
        case Overlay::Permeability: return "permeability";
        case Overlay::Density: return "density";
        case Overlay::Thickness: return "thickness";
        case Overlay::Coverage: return "coverage";
        case Overlay::Position: return "position";
        case Overlay::AreaVector: return "area";
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
        case Overlay::Permeability: return MapChannel::Permeability;
        case Overlay::Density: return MapChannel::Density;
        case Overlay::Thickness: return MapChannel::Thickness;
        default: return std::nullopt;
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
    OverlayImage image;
    if (overlay == Overlay::None) return image;
    if (const std::optional<MapChannel> channel = overlayChannel(overlay)) {
        const PaintedMap* map = document.map(body, *channel);
        if (!map) {
            image.width = image.height = 1;
            image.rgba.assign(4, 0);
            put(image, 0, rampColour(*channel == MapChannel::Permeability ? 0.0 : 1.0));
            return image;
        }
        return overlayOfMap(*map);
    }
    Result<std::shared_ptr<const SurfaceTextures>> baked = document.physicsTextures(body);
    if (!baked) return baked.error();
    const SurfaceTextures& t = **baked;
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
            case Overlay::Coverage: put(image, texel, rampColour(coverage[texel])); break;
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
            default: break;
        }
    }
    return image;
}

}  // namespace plimsoll::editor
