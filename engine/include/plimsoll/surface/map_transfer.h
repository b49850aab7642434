// Moving painted maps between parameterisations: a map painted over one UV layout (the mesh's
// own, a generated physics atlas, or an earlier version of the mesh) is resampled onto another
// through the surface, so switching atlas or editing the mesh keeps the paint.
#pragma once

#include "plimsoll/geometry/mesh.h"
#include "plimsoll/surface/painted_map.h"
#include "plimsoll/core/result.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <vector>

namespace plimsoll {

/// Nearest point of a triangle mesh's surface to a query point (uniform grid over the
/// triangles, searched in growing shells until no closer triangle can exist).
class SurfaceLocator {
public:
    explicit SurfaceLocator(const TriangleMesh& mesh);
    ~SurfaceLocator();
    SurfaceLocator(SurfaceLocator&&) noexcept;
    SurfaceLocator& operator=(SurfaceLocator&&) noexcept;

    struct Hit {
        std::uint32_t triangle = 0;
        Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();  ///< of the triangle's corners
        Eigen::Vector3d point = Eigen::Vector3d::Zero();        ///< on the surface, m
        double distance = 0;                                    ///< from the query, m
    };
    Hit nearest(const Eigen::Vector3d& query) const;

private:
    struct Grid;
    std::unique_ptr<Grid> grid_;
};

/// Resamples `map` (over `from`'s UVs, as PaintedMap lays it out) onto `to`'s UVs at
/// width x height texels. A texel of the result reached by a triangle of `to` (its centre inside
/// the triangle, or within one texel of it) shows a surface point; the value there is the map's
/// at the nearest point of `from`'s surface (the same triangle and barycentric coordinates when
/// the two meshes have the same triangles and positions, as a mesh and its physics atlas do).
/// Texels no triangle reaches take the value of the nearest reached texel, so that bilinear
/// sampling across chart borders does not pull in blank gutter. Both meshes need UVs.
Result<PaintedMap> transferPaintedMap(const PaintedMap& map, const TriangleMesh& from,
                                      const TriangleMesh& to, int width, int height);

/// Sets every texel of `map` (over `mesh`'s UVs) within one texel of the listed triangles to
/// `value`: a region of the surface painted by its triangles (the caps of a physics solid's
/// openings, which let water in).
Status paintTriangles(PaintedMap& map, const TriangleMesh& mesh,
                      const std::vector<std::uint32_t>& triangles, float value);

}  // namespace plimsoll
