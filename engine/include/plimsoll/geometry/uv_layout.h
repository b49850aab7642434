// Where the mesh's UV atlas lands in the texture. UVs inside [0,1]^2 are used as they are (so
// painted maps line up with the artist's own texture); UVs that stray outside are moved and
// uniformly scaled into the unit square, which keeps the map bijective.
#pragma once

#include "plimsoll/geometry/mesh.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

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

namespace plimsoll {

/// UV island (chart) of every triangle: triangles sharing an edge whose two vertices agree in
/// position and UV belong to one island; the two sides of a UV seam do not. Ids are the
/// smallest triangle index of each island. Requires mesh.hasUvs().
std::vector<std::uint32_t> uvIslands(const TriangleMesh& mesh);

}  // namespace plimsoll
