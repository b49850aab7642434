// The axis-aligned box as a closed mesh with six UV charts: the water graph's box compartments
// are clipped against it, and the sample meshes (samples/primitives.h) and the tests use it as
// an analytic solid.
#pragma once

#include "plimsoll/geometry/mesh.h"

#include <Eigen/Core>

namespace plimsoll {

/// Empty space between the UV charts of a generated mesh, and (half of it) around the
/// texture's edge, in UV units. Charts 0.03 apart keep bilinear and mip-mapped lookups from
/// mixing charts down to ~64 texels per side; the half-width margin gives the same gap across
/// a wrapping texture's edge.
inline constexpr double kGeneratedChartGutter = 0.03;
inline constexpr double kGeneratedChartMargin = 0.5 * kGeneratedChartGutter;

/// Axis-aligned box centred at the origin with the given edge lengths (m); six UV charts.
TriangleMesh makeBox(const Eigen::Vector3d& size);

}  // namespace plimsoll
