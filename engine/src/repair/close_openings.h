// Caps for the openings of a closed solid (physics_solid.h, Opening): the repair's own step
// after the solid is made, in openings_cgal.cpp (CGAL's corefinement) or, in a build without
// CGAL, physics_solid_unavailable.cpp.
#pragma once

#include "plimsoll/core/result.h"
#include "plimsoll/repair/openings.h"
#include "plimsoll/repair/physics_solid.h"

#include <vector>

namespace plimsoll {

/// Closes each basin of `solid` (closed and outward; its mesh's UVs are dropped) with a level cap
/// at the height where it would spill: the space below the cap and inside the walls, found
/// exactly as the part of a box up to that height not in the solid and touching none of the
/// box's sides, is joined to the solid (surgery on the points they share). The height is the
/// rim's lowest point, found from the basin's by bisection over the surface's vertex heights.
/// Adds the openings, the "cap" repair and the displacement volume.
/// Where the surgery leaves a seam open, the solid and the spaces are wrapped together
/// (settings.wrapAlpha, wrapOffset) and a "wrap" repair says so.
Status closeOpenings(PhysicsSolid& solid, const std::vector<Basin>& basins,
                     const RepairSettings& settings);

}  // namespace plimsoll
