// Internal: turning one body's sums (the PL_SUM_* slots of kernels/plimsoll_shared.h) into a
// BuoyancyResult. Shared by the C++ reference and the OpenCL backend so they cannot drift.
#pragma once

#include "plimsoll/physics/buoyancy.h"

#include "plimsoll_shared.h"

#include <array>

namespace plimsoll::detail {

using BuoyancySums = std::array<double, PL_SUM_SLOTS>;

/// `centerOfMass` in world coordinates; the sums are relative to it.
BuoyancyResult finishBuoyancy(const BuoyancySums& sums, const Eigen::Vector3d& centerOfMass,
                              const FluidSettings& fluid);

}  // namespace plimsoll::detail
