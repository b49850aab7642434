#include "plimsoll/surface/painted_map.h"

#include "plimsoll/bake/bake.h"

#include <algorithm>
#include <cstdint>

namespace plimsoll {

double PaintedMap::sample(double u, double v) const {
    if (width == 0 || height == 0) return 0.0;
    // Pixel centres sit at half-integers; row 0 is v = 1.
    const double x = std::clamp(u * width - 0.5, 0.0, width - 1.0);
    const double y = std::clamp((1.0 - v) * height - 0.5, 0.0, height - 1.0);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const double fx = x - x0, fy = y - y0;
    auto at = [&](int px, int py) { return static_cast<double>(values[py * width + px]); };
    return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) +
           fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1));
}

std::vector<double> sampleAtTexels(const PaintedMap& map, const SurfaceTextures& textures,
                                   double scale) {
    std::vector<double> out(textures.coveredCount());
    const double n = textures.size;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const std::uint32_t texel = textures.texelIndex[i];
        const Eigen::Vector2d textureUv((texel % textures.size + 0.5) / n,
                                        (texel / textures.size + 0.5) / n);
        const Eigen::Vector2d meshUv =
            (textureUv - textures.placement.offset) / textures.placement.scale;
        out[i] = scale * map.sample(meshUv.x(), meshUv.y());
    }
    return out;
}

}  // namespace plimsoll
