// Internal: the OpenCL backend, created by createBuoyancyBackend (compute_backend.cpp).
#pragma once

#include "plimsoll/compute.h"

namespace plimsoll::detail {

/// Builds the embedded kernels for device `index` of listComputeDevices().
Result<std::unique_ptr<BuoyancyBackend>> createOpenClBackend(int index);

}  // namespace plimsoll::detail
