// Compute backends for the per-frame buoyancy of many bodies: OpenCL on any device (PoCL's CPU
// device, a GPU), or the C++ reference where no OpenCL platform exists. A body's texel entries
// are uploaded once when it is added; each frame sends only poses, velocities and water.
#pragma once

#include "plimsoll/buoyancy.h"
#include "plimsoll/result.h"

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace plimsoll {

struct SurfaceTextures;

/// An OpenCL device as the loader lists it (index = position across all platforms).
struct ComputeDevice {
    int index = 0;
    std::string platform;
    std::string name;
    bool isGpu = false;
    bool hasFp64 = false;        ///< sums accumulate in double when true
    std::size_t globalMemory = 0;  ///< bytes
};

/// Every OpenCL device of every platform; empty when no platform is installed.
std::vector<ComputeDevice> listComputeDevices();

/// One body's query for one frame.
struct BodyRequest {
    std::size_t body = 0;  ///< id from addBody
    BodyFrame frame;
    FluidSettings fluid;
};

/// Where the time of the last evaluate went (ms). Device timings come from OpenCL profiling
/// events; the reference backend reports only the total.
struct FrameTimings {
    double uploadMs = 0;    ///< poses, velocities, water to the device
    double kernelMs = 0;    ///< both reduction launches
    double readbackMs = 0;  ///< totals back to the host
    double totalMs = 0;     ///< wall clock of evaluate()
};

class BuoyancyBackend {
public:
    virtual ~BuoyancyBackend() = default;

    /// "reference (C++)" or "OpenCL: <device> (<platform>)".
    virtual std::string deviceName() const = 0;

    /// Registers a body: its entries relative to its centre of mass (object space, m). Device
    /// buffers are (re)built on the next evaluate, never per frame.
    virtual std::size_t addBody(const SurfaceTextures& textures,
                                const Eigen::Vector3d& centerOfMass) = 0;

    /// Replaces a body's entries (a deforming body: same entry count, new positions and area
    /// vectors). Writes only that body's part of the device buffers.
    virtual Status updateBody(std::size_t id, const SurfaceTextures& textures,
                              const Eigen::Vector3d& centerOfMass) = 0;

    /// Evaluates every request in one batch (a few launches however many bodies); bodies not
    /// requested are skipped. results.size() == requests.size().
    virtual Status evaluate(std::span<const BodyRequest> requests, const WaterModel& water,
                            std::span<BuoyancyResult> results) = 0;

    virtual FrameTimings lastTimings() const = 0;
};

/// The C++ reference backend (double precision, every entry).
std::unique_ptr<BuoyancyBackend> createReferenceBackend();

/// Chooses a device: `spec` is "cpu", "gpu", a device index, "reference", or empty for the
/// environment variable PLIMSOLL_OPENCL_DEVICE, else the first GPU, else the first device.
/// Where no OpenCL platform exists at all, the reference backend is returned and `notice`
/// says so. Errors: an unknown spec, a requested kind that is absent, a kernel that fails to
/// build (with its build log).
Result<std::unique_ptr<BuoyancyBackend>> createBuoyancyBackend(const std::string& spec,
                                                               std::string* notice = nullptr);

/// Measures the device's copy bandwidth with a plain copy kernel (GB/s, read + write), for
/// the benchmark; `bytes` per buffer.
Result<double> measureCopyBandwidth(const std::string& spec, std::size_t bytes);

}  // namespace plimsoll
