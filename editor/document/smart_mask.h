// Smart masks: layer masks worked out from the physics and the shape instead of painted, as
// texture artists know them from their painting tools (Substance Painter's generators): the
// part of the hull below the waterline, a gradient by depth, the faces turned toward a
// direction (a deck facing up, a bottom facing down), the convex edges and curves (curvature)
// or the hollows (cavity). No GL, no files.
#pragma once

#include "document/paint.h"

#include "plimsoll/geometry/mesh.h"
#include "plimsoll/physics/pose.h"
#include "plimsoll/surface/painted_map.h"

#include <Eigen/Core>

#include <span>
#include <string>
#include <vector>

namespace plimsoll::editor {

struct SmartMask {
    enum class Kind {
        BelowWaterline,  ///< 1 below the water's level, 0 above
        Depth,           ///< 0 at the water's level, rising to 1 at `depth` below it
        Facing,          ///< how squarely the surface faces `direction`: 1 facing it, 0 side-on
        Curvature,       ///< convex mean curvature: 0 where flat or hollow, 1 from `fullCurvature`
        Cavity,          ///< concave mean curvature: 0 where flat or convex, 1 from `fullCurvature`
    };
    Kind kind = Kind::BelowWaterline;
    /// Where the body is (object -> world): its starting pose, or where the live preview shows
    /// it (a body come to rest there).
    Pose pose;
    double waterLevel = 0;  ///< world y of the still water, m
    double depth = 1;       ///< Depth: m below the level where the mask reaches 1 (> 0)
    Eigen::Vector3d direction = Eigen::Vector3d::UnitY();  ///< Facing: world, unit
    /// Curvature and Cavity: the radius of the ball the mean curvature is measured over (m, > 0;
    /// features narrower than it are smoothed over, a crease marks a band this wide each side)
    double radius = 0.05;
    /// Curvature and Cavity: the mean curvature at which the mask reaches 1 (1/m, > 0; a sphere
    /// of radius R has 1/R)
    double fullCurvature = 5;
};

/// "below the waterline", "by depth", "facing", "curvature", "cavity" (the history's step
/// names).
std::string smartMaskName(SmartMask::Kind kind);

/// The signed mean curvature of the mesh around each point (1/m; positive convex, negative
/// concave), measured over the ball of `radius` about it as the normal cycle's mean-curvature
/// measure (Cohen-Steiner and Morvan 2003): every edge of the mesh (vertices welded by
/// position, so UV seams are no edges) carries its dihedral turn theta (the angle between its
/// two faces' normals, negative where the edge is concave), and
///     H(p) = sum over edges of theta_e * |e inside the ball| / 2, divided by pi radius^2,
/// the area of a flat disc of that radius (and exactly the area a sphere of any radius has
/// inside the ball about a point on it: Archimedes' cap). On a sphere of radius R tessellated
/// finer than `radius` it is 1/R everywhere, on a flat face farther than `radius` from every
/// crease exactly 0, on a convex mesh never negative. Edges with other than two faces count
/// nothing.
std::vector<double> meanCurvatureAt(const TriangleMesh& mesh,
                                    std::span<const Eigen::Vector3f> points, double radius);

/// The mask over the map's pixel grid (`surface`'s width x height): each pixel the mean of its
/// pieces of surface (PaintSurface samples) at their places and normals as posed; pixels no
/// surface reaches are 0. Curvature and Cavity need the mesh the surface was built from (their
/// mask is all 0 without one) and do not depend on the pose.
PaintedMap smartMaskImage(const PaintSurface& surface, const SmartMask& mask,
                          const TriangleMesh* mesh = nullptr);

}  // namespace plimsoll::editor
