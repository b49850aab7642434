// Internal: the OpenCL backend, created by createBuoyancyBackend (compute_backend.cpp).
#pragma once

#include "plimsoll/compute.h"

namespace plimsoll::detail {

/// Builds the embedded kernels for device `index` of listComputeDevices().
Result<std::unique_ptr<BuoyancyBackend>> createOpenClBackend(int index);

/// Compiles `source` (after the shared header) for device `index`, as the backend compiles
/// its kernels: Ok, or an error carrying the device's build log. Lets tests check that a
/// broken kernel is reported with its log.
Status compileKernelSource(int index, const std::string& source);

}  // namespace plimsoll::detail
