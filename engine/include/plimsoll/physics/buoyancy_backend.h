// What every compute backend offers the simulation: a body's entries uploaded once when it is
// added, then each frame only poses, velocities and water; and the water graph's exchange pass
// over its permeable samples. The backends themselves (OpenCL, the fast CPU path, the C++
// reference) are built in compute/; the scene and the graph see only this interface.
#pragma once

#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/core/result.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace plimsoll {

struct SurfaceTextures;

/// One body's query for one frame.
struct BodyRequest {
    std::size_t body = 0;  ///< id from addBody
    BodyFrame frame;
    FluidSettings fluid;
};

/// One permeable texel of a body with a water graph (graph.h, paper 4.2): where it is, how
/// much passes through it, and the node it feeds.
struct ExchangeSample {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< object space, m
    double weight = 0;                                   ///< permeability (0..1) x area, m^2
    std::uint32_t node = 0;                              ///< the node it feeds
};

/// One body's exchange pass for one frame. At a sample with outside depth d_out (below the
/// water surface, >= 0) and inside head d_in (below its node's water surface, >= 0), the head
/// h = d_out - d_in drives |q| = factor w |h| (linear) or factor w sqrt|h| (Torricelli, factor
/// = C_d sqrt(2 g)); h > 0 flows in, h < 0 out.
struct ExchangeFrame {
    Pose pose;                            ///< object -> world
    double time = 0;                      ///< s, for moving water
    std::span<const double> nodeSurface;  ///< world height of each node's water, m (-inf: none)
    bool torricelli = false;
    double factor = 1.0;  ///< 1/s (linear) or m^0.5/s (Torricelli)
};

/// Per-node sums of an exchange pass.
struct ExchangeSums {
    std::vector<double> inflow;   ///< m^3/s into each node
    std::vector<double> outflow;  ///< m^3/s out of each node
    /// Highest outside surface over the samples flowing into the node (world m; -inf: none).
    std::vector<double> outsideTop;
};

/// The C++ reference of the exchange pass (double precision, every sample): the oracle the
/// OpenCL kernel (kernels/graph.cl) is tested against. The outside surface is the water's on
/// the exchange's world lattice, interpolated (plimsoll_eval/graph.hpp exchangeSurfaces: one
/// height per lattice node the samples touch, as the runtime asks a game's water). `sums` is
/// resized to `nodes`.
void evaluateExchangeReference(std::span<const ExchangeSample> samples, std::size_t nodes,
                               const ExchangeFrame& frame, const WaterModel& water,
                               ExchangeSums& sums);

/// The exchange pass with the water's own height at every sample (how the pass took the water
/// before the lattice): the reference the lattice's error is measured against.
void evaluateExchangePointwise(std::span<const ExchangeSample> samples, std::size_t nodes,
                               const ExchangeFrame& frame, const WaterModel& water,
                               ExchangeSums& sums);

/// Where the time of the last evaluate went (ms). Device timings come from OpenCL profiling
/// events, where OpenClOptions::deviceTimings asks for them; the CPU backends report only the
/// total.
struct FrameTimings {
    double uploadMs = 0;    ///< poses, velocities, water to the device
    double kernelMs = 0;    ///< both reduction launches
    double reduceMs = 0;    ///< of kernelMs, the second launch: the per-body sums of the tiles
    double readbackMs = 0;  ///< totals back to the host
    double totalMs = 0;     ///< wall clock of evaluate()
};

/// How the tiles of the last evaluate were treated, summed over the bodies asked for: what the
/// tile scheme saved (the OpenCL path; the others report none).
struct TileCounts {
    std::size_t tiles = 0;           ///< of the bodies asked for
    std::size_t dry = 0;             ///< nothing read
    std::size_t closedForm = 0;      ///< hydrostatics from the tile's moments
    std::size_t dragClosedForm = 0;  ///< drag from the tile's moments too
    std::size_t perEntry() const { return tiles - dry - closedForm; }
};

/// What computes a backend's sums: what callers branch on (falling back from a failed
/// device, labelling results), where the device name is only for people.
enum class BackendKind {
    reference,  ///< the C++ reference (double precision, every entry)
    fastCpu,    ///< the fast CPU path (float32 tiles, closed form away from the waterline)
    openClCpu,  ///< OpenCL on a CPU device (PoCL, ...)
    openClGpu,  ///< OpenCL on a GPU
};

/// "reference", "fast-cpu", "opencl-cpu", "opencl-gpu": the kind as JSON and logs print it.
constexpr const char* backendKindName(BackendKind kind) {
    switch (kind) {
        case BackendKind::reference:
            return "reference";
        case BackendKind::fastCpu:
            return "fast-cpu";
        case BackendKind::openClCpu:
            return "opencl-cpu";
        case BackendKind::openClGpu:
            return "opencl-gpu";
    }
    return "reference";
}

/// True for the backends that run on an OpenCL device (and so can fail as a device does).
constexpr bool isOpenCl(BackendKind kind) {
    return kind == BackendKind::openClCpu || kind == BackendKind::openClGpu;
}

class BuoyancyBackend {
public:
    virtual ~BuoyancyBackend() = default;

    virtual BackendKind kind() const = 0;

    /// "reference (C++)", "fast CPU (N threads)" or "OpenCL: <device> (<platform>)".
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

    virtual TileCounts lastTileCounts() const { return {}; }

    /// Runs work(i) for every i in [0, count), each once, and returns when all are done: on
    /// the backend's CPU workers where it has them (the fast path's threads, or the caller's
    /// task system), in order on the calling thread otherwise. For the caller's per-body work
    /// between evaluations (integrating independent bodies); `work` must not touch what
    /// another i touches.
    virtual void forEach(std::size_t count, const std::function<void(std::size_t)>& work) {
        for (std::size_t i = 0; i < count; ++i) work(i);
    }

    /// Registers the permeable samples of a body's water graph, feeding `nodes` nodes (at most
    /// kMaxExchangeNodes). Returns the set's id for evaluateExchange.
    virtual std::size_t addExchangeSet(std::span<const ExchangeSample> samples,
                                       std::size_t nodes) = 0;

    /// One pass over a set's samples, summed per node (paper 4.2: one kernel pass).
    virtual Status evaluateExchange(std::size_t set, const ExchangeFrame& frame,
                                    const WaterModel& water, ExchangeSums& sums) = 0;
};

/// Nodes one exchange set may feed (the kernel's per-node sums live in local memory).
inline constexpr std::size_t kMaxExchangeNodes = 256;

}  // namespace plimsoll
