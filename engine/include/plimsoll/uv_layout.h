// Where the mesh's UV atlas lands in the texture. UVs inside [0,1]^2 are used as they are (so
// painted maps line up with the artist's own texture); UVs that stray outside are moved and
// uniformly scaled into the unit square, which keeps the map bijective.
#pragma once

#include "plimsoll/mesh.h"

#include <Eigen/Core>

namespace plimsoll {

/// texture uv = scale * mesh uv + offset.
struct UvPlacement {
    double scale = 1.0;
    Eigen::Vector2d offset = Eigen::Vector2d::Zero();

    Eigen::Vector2d apply(const Eigen::Vector2d& uv) const { return scale * uv + offset; }
    bool isIdentity() const { return scale == 1.0 && offset.isZero(); }
};

/// Identity when every UV lies in [0,1]^2; otherwise the uniform scale and offset that fit the
/// UV bounding box into the unit square (anchored at the origin). Requires mesh.hasUvs().
UvPlacement fitUvsIntoUnitSquare(const TriangleMesh& mesh);

}  // namespace plimsoll
