// A build without OpenCL (PLIMSOLL_WITH_OPENCL=OFF): no devices, and every request for one is
// refused as unsupported, so that callers fall back to the C++ reference path or say why not.
#include "compute/opencl_backend.h"

namespace plimsoll {

namespace {

Error noOpenCl(const std::string& what) {
    return makeError(
        ErrorKind::unsupported,
        what + ": this build has no OpenCL (configured with PLIMSOLL_WITH_OPENCL=OFF)");
}

}  // namespace

bool openClAvailable() { return false; }

std::vector<ComputeDevice> listComputeDevices() { return {}; }

Result<double> measureCopyBandwidth(const std::string& spec, std::size_t) {
    return noOpenCl("OpenCL device '" + spec + "'");
}

namespace detail {

Result<std::unique_ptr<BuoyancyBackend>> createOpenClBackend(int index, const OpenClOptions&) {
    return noOpenCl("OpenCL device " + std::to_string(index));
}

Status compileKernelSource(int index, const std::string&) {
    return noOpenCl("OpenCL device " + std::to_string(index));
}

// Nothing to inject faults into or to limit.
void failOpenClCallsForTesting(OpenClFault, int) {}
void setOpenClMemoryLimitsForTesting(std::uint64_t, std::uint64_t) {}

}  // namespace detail

}  // namespace plimsoll
