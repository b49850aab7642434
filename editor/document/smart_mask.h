// Smart masks: layer masks worked out from the physics and the shape instead of painted, as
// texture artists know them from their painting tools (Substance Painter's generators): the
// part of the hull below the waterline, a gradient by depth, or the faces turned toward a
// direction (a deck facing up, a bottom facing down). No GL, no files.
#pragma once

#include "document/paint.h"

#include "plimsoll/physics/pose.h"
#include "plimsoll/surface/painted_map.h"

#include <Eigen/Core>

#include <string>

namespace plimsoll::editor {

struct SmartMask {
    enum class Kind {
        BelowWaterline,  ///< 1 below the water's level, 0 above
        Depth,           ///< 0 at the water's level, rising to 1 at `depth` below it
        Facing,          ///< how squarely the surface faces `direction`: 1 facing it, 0 side-on
    };
    Kind kind = Kind::BelowWaterline;
    /// Where the body is (object -> world): its starting pose, or where the live preview shows
    /// it (a body come to rest there).
    Pose pose;
    double waterLevel = 0;  ///< world y of the still water, m
    double depth = 1;       ///< Depth: m below the level where the mask reaches 1 (> 0)
    Eigen::Vector3d direction = Eigen::Vector3d::UnitY();  ///< Facing: world, unit
};

/// "below the waterline", "by depth", "facing" (the history's step names).
std::string smartMaskName(SmartMask::Kind kind);

/// The mask over the map's pixel grid (`surface`'s width x height): each pixel the mean of its
/// pieces of surface (PaintSurface samples) at their places and normals as posed; pixels no
/// surface reaches are 0.
PaintedMap smartMaskImage(const PaintSurface& surface, const SmartMask& mask);

}  // namespace plimsoll::editor
