// Smart masks (smart_mask.h).
#include "document/smart_mask.h"

#include <algorithm>
#include <vector>

namespace plimsoll::editor {

std::string smartMaskName(SmartMask::Kind kind) {
    switch (kind) {
        case SmartMask::Kind::BelowWaterline:
            return "below the waterline";
        case SmartMask::Kind::Depth:
            return "by depth";
        case SmartMask::Kind::Facing:
            return "facing";
    }
    return "smart";
}

PaintedMap smartMaskImage(const PaintSurface& surface, const SmartMask& mask) {
    PaintedMap out;
    out.width = surface.width;
    out.height = surface.height;
    const std::size_t pixels = std::size_t(surface.width) * std::size_t(surface.height);
    std::vector<double> sum(pixels, 0.0);
    std::vector<int> count(pixels, 0);
    const Eigen::Vector3d direction = mask.direction.normalized();
    for (std::size_t k = 0; k < surface.sampleCount(); ++k) {
        const Eigen::Vector3d p = mask.pose.apply(surface.position[k].cast<double>());
        const double below = mask.waterLevel - p.y();
        double value = 0;
        switch (mask.kind) {
            case SmartMask::Kind::BelowWaterline:
                value = below > 0 ? 1.0 : 0.0;
                break;
            case SmartMask::Kind::Depth:
                value = std::clamp(below / std::max(mask.depth, 1e-9), 0.0, 1.0);
                break;
            case SmartMask::Kind::Facing:
                value = std::max(
                    0.0, (mask.pose.rotation * surface.normal[k].cast<double>()).dot(direction));
                break;
        }
        sum[surface.pixel[k]] += value;
        ++count[surface.pixel[k]];
    }
    out.values.resize(pixels, 0.0f);
    for (std::size_t i = 0; i < pixels; ++i) {
        if (count[i] > 0) out.values[i] = static_cast<float>(sum[i] / count[i]);
    }
    return out;
}

}  // namespace plimsoll::editor
