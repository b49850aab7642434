#include "plimsoll/uv_layout.h"

#include <algorithm>

namespace plimsoll {

UvPlacement fitUvsIntoUnitSquare(const TriangleMesh& mesh) {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300);
    Eigen::Vector2d hi = Eigen::Vector2d::Constant(-1e300);
    for (const auto& uv : mesh.uvs) {
        lo = lo.cwiseMin(uv);
        hi = hi.cwiseMax(uv);
    }
    UvPlacement placement;
    if (mesh.uvs.empty() || (lo.minCoeff() >= 0.0 && hi.maxCoeff() <= 1.0)) return placement;
    const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
    placement.scale = extent > 0 ? 1.0 / extent : 1.0;
    placement.offset = -placement.scale * lo;
    return placement;
}

}  // namespace plimsoll
