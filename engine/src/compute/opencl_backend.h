// Internal: the OpenCL backend, created by createBuoyancyBackend (compute_backend.cpp).
#pragma once

#include "plimsoll/compute/compute.h"

#include <cstdint>

namespace plimsoll::detail {

/// Builds the embedded kernels for device `index` of listComputeDevices().
Result<std::unique_ptr<BuoyancyBackend>> createOpenClBackend(int index,
                                                             const OpenClOptions& options = {});

/// Compiles `source` (after the shared header) for device `index`, as the backend compiles
/// its kernels: Ok, or an error carrying the device's build log. Lets tests check that a
/// broken kernel is reported with its log.
Status compileKernelSource(int index, const std::string& source);

/// Kinds of OpenCL failure a test can inject (failOpenClCallsForTesting), each thrown where a
/// real device fails that way, with the code it gives.
enum class OpenClFault {
    BufferAllocation,  ///< clCreateBuffer: CL_MEM_OBJECT_ALLOCATION_FAILURE
    Launch,            ///< clEnqueueNDRangeKernel: CL_OUT_OF_RESOURCES
    Build,             ///< clBuildProgram: CL_BUILD_PROGRAM_FAILURE
    LostDevice,        ///< clEnqueueReadBuffer: CL_DEVICE_NOT_AVAILABLE (device gone)
};

/// Test hook: the next `count` calls of `kind` fail (0 turns it off). Like file_util's
/// failFileStepForTesting; not for production use.
void failOpenClCallsForTesting(OpenClFault kind, int count);

/// Test hook: pretend the device allows buffers of at most `maxAllocation` bytes and has
/// `globalMemory` bytes (0: the device's own values).
void setOpenClMemoryLimitsForTesting(std::uint64_t maxAllocation, std::uint64_t globalMemory);

}  // namespace plimsoll::detail
