// Compute backends for the per-frame buoyancy of many bodies: OpenCL on any device (PoCL's CPU
// device, a GPU), the fast CPU path (fast_backend.h) or the C++ reference, chosen here. The
// interface they share (BuoyancyBackend) is the core's (physics/buoyancy_backend.h).
#pragma once

#include "plimsoll/physics/buoyancy_backend.h"
#include "plimsoll/core/result.h"

#include <cstddef>
#include <cstdint>
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
    bool hasFp64 = false;          ///< sums accumulate in double when true
    std::size_t globalMemory = 0;  ///< bytes
};

/// Every OpenCL device of every platform; empty when no platform is installed.
std::vector<ComputeDevice> listComputeDevices();

/// False in a build configured without OpenCL (PLIMSOLL_WITH_OPENCL=OFF): no device is listed,
/// and a device asked for by name is refused with ErrorKind::unsupported.
bool openClAvailable();

/// How the OpenCL path's evaluate() waits for the device's totals.
/// Measured (docs/design.md, "Waiting for the totals"): on an H200 the two are within the noise
/// (the spin the less steady on waves); on PoCL spinning costs 1.3-2x, its workers needing the
/// cores. So every device blocks unless asked.
enum class OpenClWait {
    automatic,  ///< the measured best for the device: block, on GPUs and CPU devices alike
    block,      ///< a blocking read: the driver puts the thread to sleep and wakes it
    spin,       ///< the read is queued and its event polled: the thread keeps its core
};

/// The OpenCL path's knobs (each measured beside the default by plimsoll bench --realtime).
struct OpenClOptions {
    /// On waves a tile is summed from its moments (or found dry) under the water's quadratic
    /// over it only where that quadratic misses the surface, at 16 points between the 9 it was
    /// fitted to, by at most this fraction of the body's radius; else entry by entry under the
    /// true surface. 0: every tile that reaches the water on waves is summed entry by entry.
    /// The closed forms' depth error is then about this misfit, so the pressure force's is
    /// about rho g (waveTolerance x radius) x the wetted area. Flat water is exact either way.
    double waveTolerance = 1e-3;
    /// How evaluate() waits for the totals: a speed knob, the sums are the same.
    OpenClWait wait = OpenClWait::automatic;
    /// Fill lastTimings()' upload, kernel and read-back times from profiling events (the
    /// benchmark's split). Off, the queue records no timestamps and only totalMs is filled.
    /// On an H200 the events cost 25-30 us a frame, half of a 2048^2 frame (docs/design.md).
    bool deviceTimings = false;
    /// Entries each work-item sums per tile, 1 to kMaxOpenClItemsPerThread; a tile is
    /// kOpenClWorkGroupSize times as many entries. 0: the device's default, 8 (fastest on
    /// PoCL, whose cost is per group). Fewer, smaller tiles shorten the longest group's chain on
    /// a GPU, whose lone body leaves most of it idle. A speed knob: on flat water the sums agree
    /// to rounding; on waves a tile's closed form under the water's quadratic is taken where
    /// that tile passes the tolerance, so smaller tiles pass more often.
    int itemsPerThread = 0;
};
inline constexpr int kMaxOpenClItemsPerThread = 64;
/// Work-items in each of the OpenCL kernels' groups (PL_WORKGROUP_SIZE in the kernels' shared
/// header, which the backend checks against this).
inline constexpr int kOpenClWorkGroupSize = 128;

/// The C++ reference backend (double precision, every entry).
std::unique_ptr<BuoyancyBackend> createReferenceBackend();

/// Chooses a device: `spec` is "fast", "cpu", "gpu", a device index, "reference", or empty for
/// PLIMSOLL_OPENCL_DEVICE, else the first GPU, else the fast CPU path (fast_backend.h). Where
/// no OpenCL platform exists, or the automatically chosen GPU fails (its kernels do not
/// build), the fast CPU path is returned and `notice` says why. Errors: an unknown spec, a
/// requested kind that is absent, a kernel that fails to build (with its build log).
Result<std::unique_ptr<BuoyancyBackend>> createBuoyancyBackend(const std::string& spec,
                                                               std::string* notice = nullptr,
                                                               const OpenClOptions& openCl = {});

/// Measures the device's copy bandwidth with a plain copy kernel (GB/s, read + write), for
/// the benchmark; `bytes` per buffer.
Result<double> measureCopyBandwidth(const std::string& spec, std::size_t bytes);

}  // namespace plimsoll
