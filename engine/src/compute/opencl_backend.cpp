// The OpenCL backend: device discovery, the embedded kernels (kernels/buoyancy.cl), buffers
// built once per set of bodies, and one batch of two launches and one read per frame.
#include "compute/opencl_backend.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/core/limits.h"

#include "physics/buoyancy_sums.h"
#include "plimsoll_shared.h"
#include "plimsoll_eval/fast.hpp"   // kPair, kTriple: PlTileMoments' slots
#include "plimsoll_eval/graph.hpp"  // kExchangeLatticeSpacing

#include <CL/opencl.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>

namespace plimsoll::detail {
extern const char* const kBuoyancyKernelSource;
}  // namespace plimsoll::detail

namespace plimsoll {

namespace {

using gpu::pl_float4;

struct DeviceHandle {
    cl::Platform platform;
    cl::Device device;
};

std::vector<DeviceHandle> enumerateDevices() {
    std::vector<DeviceHandle> out;
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error&) {
        return out;  // no ICD installed: CL_PLATFORM_NOT_FOUND_KHR
    }
    for (const cl::Platform& platform : platforms) {
        std::vector<cl::Device> devices;
        try {
            platform.getDevices(CL_DEVICE_TYPE_ALL, &devices);
        } catch (const cl::Error&) {
            continue;  // a platform without devices
        }
        for (const cl::Device& device : devices) out.push_back({platform, device});
    }
    return out;
}

/// The CL_* name of an OpenCL error code (the numbers alone send users to the header).
std::string clErrorName(cl_int code) {
    switch (code) {
#define PL_CL_CODE(name) \
    case name:           \
        return #name;
        PL_CL_CODE(CL_DEVICE_NOT_FOUND)
        PL_CL_CODE(CL_DEVICE_NOT_AVAILABLE)
        PL_CL_CODE(CL_COMPILER_NOT_AVAILABLE)
        PL_CL_CODE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        PL_CL_CODE(CL_OUT_OF_RESOURCES)
        PL_CL_CODE(CL_OUT_OF_HOST_MEMORY)
        PL_CL_CODE(CL_PROFILING_INFO_NOT_AVAILABLE)
        PL_CL_CODE(CL_BUILD_PROGRAM_FAILURE)
        PL_CL_CODE(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        PL_CL_CODE(CL_INVALID_VALUE)
        PL_CL_CODE(CL_INVALID_DEVICE)
        PL_CL_CODE(CL_INVALID_CONTEXT)
        PL_CL_CODE(CL_INVALID_COMMAND_QUEUE)
        PL_CL_CODE(CL_INVALID_MEM_OBJECT)
        PL_CL_CODE(CL_INVALID_PROGRAM)
        PL_CL_CODE(CL_INVALID_PROGRAM_EXECUTABLE)
        PL_CL_CODE(CL_INVALID_KERNEL_NAME)
        PL_CL_CODE(CL_INVALID_KERNEL)
        PL_CL_CODE(CL_INVALID_ARG_INDEX)
        PL_CL_CODE(CL_INVALID_ARG_VALUE)
        PL_CL_CODE(CL_INVALID_ARG_SIZE)
        PL_CL_CODE(CL_INVALID_KERNEL_ARGS)
        PL_CL_CODE(CL_INVALID_WORK_DIMENSION)
        PL_CL_CODE(CL_INVALID_WORK_GROUP_SIZE)
        PL_CL_CODE(CL_INVALID_WORK_ITEM_SIZE)
        PL_CL_CODE(CL_INVALID_GLOBAL_OFFSET)
        PL_CL_CODE(CL_INVALID_EVENT)
        PL_CL_CODE(CL_INVALID_OPERATION)
        PL_CL_CODE(CL_INVALID_BUFFER_SIZE)
        PL_CL_CODE(CL_INVALID_GLOBAL_WORK_SIZE)
        PL_CL_CODE(CL_INVALID_BUILD_OPTIONS)
#undef PL_CL_CODE
        case -1001:
            return "CL_PLATFORM_NOT_FOUND_KHR";
        default:
            return "unknown OpenCL error";
    }
}

/// "clEnqueueNDRangeKernel failed: CL_OUT_OF_RESOURCES (-5)": the failing call and the code.
std::string clError(const cl::Error& e) {
    return std::string(e.what() ? e.what() : "OpenCL call") + " failed: " + clErrorName(e.err()) +
           " (" + std::to_string(e.err()) + ")";
}

/// Device limits replaced by a test (0: the device's own).
std::atomic<cl_ulong> testMaxAlloc{0}, testGlobalMemory{0};

/// Injected faults still to fire, per kind (detail::failOpenClCallsForTesting).
std::array<std::atomic<int>, 4> injectedFaults{};

/// Where a real device can fail in `kind`'s way: throws what the driver would while an
/// injected fault of that kind is pending.
void faultPoint(detail::OpenClFault kind, const char* call) {
    std::atomic<int>& left = injectedFaults[static_cast<int>(kind)];
    int n = left.load();
    while (n > 0 && !left.compare_exchange_weak(n, n - 1)) {
    }
    if (n <= 0) return;
    switch (kind) {
        case detail::OpenClFault::BufferAllocation:
            throw cl::Error(CL_MEM_OBJECT_ALLOCATION_FAILURE, call);
        case detail::OpenClFault::Launch:
            throw cl::Error(CL_OUT_OF_RESOURCES, call);
        case detail::OpenClFault::Build:
            throw cl::Error(CL_BUILD_PROGRAM_FAILURE, call);
        case detail::OpenClFault::LostDevice:
            throw cl::Error(CL_DEVICE_NOT_AVAILABLE, call);
    }
}

// The kernels read these structs as the C++ side lays them out (plimsoll_shared.h), and the
// public header states their group size.
static_assert(PL_WORKGROUP_SIZE == kOpenClWorkGroupSize);
static_assert(sizeof(gpu::PlTile) == 48 && sizeof(gpu::PlTileMoments) == 256 &&
              sizeof(gpu::PlBody) == 160);

pl_float4 toFloat4(const Eigen::Vector3d& v, double w = 0.0) {
    return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()),
            static_cast<float>(w)};
}

/// Tiles per work-group of the second launch (reduce_chunks): 128 tiles of 21 sums are 21
/// loads per summing work-item. A 2048^2 body has 4096 tiles, 32 chunks.
constexpr std::uint32_t kTilesPerChunk = 128;

double eventMs(const cl::Event& event) {
    const auto start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    const auto end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    return static_cast<double>(end - start) * 1e-6;
}

/// Compiles the embedded kernels for a device, with the build log in the error.
Result<cl::Program> buildProgram(const cl::Context& context, const cl::Device& device, bool fp64,
                                 int itemsPerThread,
                                 const std::string& source = detail::kBuoyancyKernelSource) {
    cl::Program program(context, source);
    const std::string options =
        "-cl-std=CL1.2 -DPL_ITEMS_PER_THREAD=" + std::to_string(itemsPerThread) +
        (fp64 ? " -DPL_ACC_DOUBLE" : "");
    try {
        faultPoint(detail::OpenClFault::Build, "clBuildProgram");
        program.build({device}, options.c_str());
    } catch (const cl::Error& e) {
        std::string log;
        try {
            log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
        } catch (const cl::Error&) {
        }
        return makeError(ErrorKind::kernelBuild, "OpenCL kernels failed to build on " +
                                                     device.getInfo<CL_DEVICE_NAME>() + " (" +
                                                     clError(e) + "):\n" + log);
    }
    return program;
}

/// Host memory the driver copies to and from directly: a CL_MEM_ALLOC_HOST_PTR buffer, mapped
/// once for its whole life. NVIDIA's OpenCL best-practices guide gives this as the way to
/// pinned memory; from ordinary (pageable) memory the driver goes through a staging copy of
/// its own. The frame's parameters go up from, and its totals come back into, these (bytes:
/// the parameters hold two kinds of record, the totals floats or doubles by device).
class PinnedBytes {
public:
    PinnedBytes() = default;
    PinnedBytes(const PinnedBytes&) = delete;  // one mapping, unmapped once
    PinnedBytes& operator=(const PinnedBytes&) = delete;

    /// `size` zeroed bytes; the old block is unmapped first.
    void allocate(const cl::Context& context, cl::CommandQueue& queue, std::size_t size) {
        release(queue);
        const std::size_t bytes = std::max<std::size_t>(1, size);
        buffer_ = cl::Buffer(context, CL_MEM_ALLOC_HOST_PTR | CL_MEM_READ_WRITE, bytes);
        data_ = static_cast<unsigned char*>(
            queue.enqueueMapBuffer(buffer_, CL_TRUE, CL_MAP_READ | CL_MAP_WRITE, 0, bytes));
        size_ = size;
        std::fill_n(data_, size_, 0);
    }

    /// Unmaps and lets the buffer go (a lost device: the buffer goes anyway).
    void release(cl::CommandQueue& queue) noexcept {
        if (data_) {
            try {
                queue.enqueueUnmapMemObject(buffer_, data_);
                queue.finish();
            } catch (const cl::Error&) {
            }
        }
        buffer_ = cl::Buffer();
        data_ = nullptr;
        size_ = 0;
    }

    unsigned char* data() { return data_; }
    std::size_t size() const { return size_; }

private:
    cl::Buffer buffer_;
    unsigned char* data_ = nullptr;
    std::size_t size_ = 0;
};

class OpenClBackend final : public BuoyancyBackend {
public:
    OpenClBackend(const DeviceHandle& handle, cl::Context context, cl::Program program, bool fp64,
                  std::size_t tileSize, const OpenClOptions& options)
        : device_(handle.device),
          context_(std::move(context)),
          queue_(
              context_, device_,
              options.deviceTimings ? cl_command_queue_properties{CL_QUEUE_PROFILING_ENABLE} : 0),
          program_(std::move(program)),
          tilesKernels_{{{cl::Kernel(program_, "buoyancy_tiles_flat"),
                          cl::Kernel(program_, "buoyancy_tiles_flat_still")},
                         {cl::Kernel(program_, "buoyancy_tiles_gerstner"),
                          cl::Kernel(program_, "buoyancy_tiles_gerstner_still")},
                         {cl::Kernel(program_, "buoyancy_tiles_heightfield"),
                          cl::Kernel(program_, "buoyancy_tiles_heightfield_still")}}},
          reduceKernel_(program_, "reduce_chunks"),
          exchangeKernels_{{cl::Kernel(program_, "graph_exchange_flat"),
                            cl::Kernel(program_, "graph_exchange_gerstner"),
                            cl::Kernel(program_, "graph_exchange_heightfield")}},
          fp64_(fp64),
          tileSize_(tileSize),
          options_(options),
          name_("OpenCL: " + device_.getInfo<CL_DEVICE_NAME>() + " (" +
                handle.platform.getInfo<CL_PLATFORM_NAME>() + ")"),
          // Asked once: a lost device answers no more queries.
          kind_((device_.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_GPU) != 0
                    ? BackendKind::openClGpu
                    : BackendKind::openClCpu),
          spinWait_(options.wait == OpenClWait::spin) {}

    // Writes are enqueued non-blocking from host memory this backend owns: after a failed
    // call, or before that memory goes, the queue is drained so the device never reads freed
    // or rewritten memory (ASan saw PoCL read a freed vector after a fault-injected launch).
    ~OpenClBackend() override {
        drainQueue();
        frameParams_.release(queue_);
        totalsHost_.release(queue_);
    }

    void drainQueue() {
        try {
            queue_.finish();
        } catch (const cl::Error&) {  // a lost device: nothing is in flight any more
        }
    }

    BackendKind kind() const override { return kind_; }

    std::string deviceName() const override { return name_; }

    std::size_t addBody(const SurfaceTextures& textures,
                        const Eigen::Vector3d& centerOfMass) override {
        Body body;
        body.centerOfMass = centerOfMass;
        body.firstEntry = positions_.size();
        body.tileBegin = static_cast<std::uint32_t>(tiles_.size());
        // Tiles are square blocks of texels, not runs of rows: a block is a compact patch of
        // surface, so its bounding sphere is small and whole blocks drop out (dry) or take
        // the closed form (under flat water) in any orientation. Sums do not care about order.
        body.order = blockOrder(textures);
        const std::uint32_t blockSide = blockSideFor(tileSize_);
        std::size_t begin = 0;
        while (begin < body.order.size()) {
            const std::uint32_t block =
                blockOf(textures.texelIndex[body.order[begin]], textures.size, blockSide);
            std::size_t end = begin + 1;
            while (end < body.order.size() && end - begin < tileSize_ &&
                   blockOf(textures.texelIndex[body.order[end]], textures.size, blockSide) == block)
                ++end;
            body.tileEnds.push_back(end);
            tiles_.emplace_back();
            tileMoments_.emplace_back();
            begin = end;
        }
        positions_.resize(positions_.size() + body.order.size());
        areaVectors_.resize(areaVectors_.size() + body.order.size());
        body.tileEnd = static_cast<std::uint32_t>(tiles_.size());
        bodies_.push_back(std::move(body));
        fillBody(bodies_.size() - 1, textures);
        buffersStale_ = true;
        return bodies_.size() - 1;
    }

    Status updateBody(std::size_t id, const SurfaceTextures& textures,
                      const Eigen::Vector3d& centerOfMass) override {
        if (id >= bodies_.size())
            return makeError(ErrorKind::invalidArgument, "updateBody: unknown body id");
        Body& body = bodies_[id];
        if (textures.coveredCount() != body.order.size()) {
            return makeError(ErrorKind::invalidArgument,
                             "updateBody: the entry count changed (" +
                                 std::to_string(body.order.size()) + " -> " +
                                 std::to_string(textures.coveredCount()) + ")");
        }
        body.centerOfMass = centerOfMass;
        fillBody(id, textures);
        if (buffersStale_) return Ok{};
        try {
            const std::size_t entries = body.order.size();
            const std::size_t tiles = body.tileEnd - body.tileBegin;
            queue_.enqueueWriteBuffer(positionsBuffer_, CL_FALSE,
                                      body.firstEntry * sizeof(pl_float4),
                                      entries * sizeof(pl_float4), &positions_[body.firstEntry]);
            queue_.enqueueWriteBuffer(areaVectorsBuffer_, CL_FALSE,
                                      body.firstEntry * sizeof(pl_float4),
                                      entries * sizeof(pl_float4), &areaVectors_[body.firstEntry]);
            queue_.enqueueWriteBuffer(tilesBuffer_, CL_FALSE, body.tileBegin * sizeof(gpu::PlTile),
                                      tiles * sizeof(gpu::PlTile), &tiles_[body.tileBegin]);
            queue_.enqueueWriteBuffer(
                tileMomentsBuffer_, CL_TRUE, body.tileBegin * sizeof(gpu::PlTileMoments),
                tiles * sizeof(gpu::PlTileMoments), &tileMoments_[body.tileBegin]);
        } catch (const cl::Error& e) {
            drainQueue();
            return makeError(ErrorKind::device, name_ + ": " + clError(e));
        }
        return Ok{};
    }

    Status evaluate(std::span<const BodyRequest> requests, const WaterModel& water,
                    std::span<BuoyancyResult> results) override {
        const auto start = std::chrono::steady_clock::now();
        try {
            if (buffersStale_) rebuildBuffers();
            if (Status s = prepareFrame(requests, water); !s.ok()) return s;
            runFrame(tilesKernelFor(requests, water), water.kind == WaterModel::Kind::Gerstner);
            tileCounts_ = {};
            const std::size_t accSize = fp64_ ? sizeof(double) : sizeof(float);
            for (std::size_t i = 0; i < requests.size(); ++i) {
                const Body& body = bodies_[requests[i].body];
                detail::BuoyancySums sums{};
                for (std::uint32_t c = body.chunkBegin; c < body.chunkEnd; ++c) {
                    const unsigned char* base = totalsHost_.data() + c * PL_SUM_SLOTS * accSize;
                    for (int s = 0; s < PL_SUM_SLOTS; ++s) {
                        sums[s] += fp64_ ? reinterpret_cast<const double*>(base)[s]
                                         : reinterpret_cast<const float*>(base)[s];
                    }
                }
                tileCounts_.tiles += body.tileEnd - body.tileBegin;
                tileCounts_.dry += static_cast<std::size_t>(std::llround(sums[PL_SUM_TILES_DRY]));
                tileCounts_.closedForm +=
                    static_cast<std::size_t>(std::llround(sums[PL_SUM_TILES_CLOSED]));
                tileCounts_.dragClosedForm +=
                    static_cast<std::size_t>(std::llround(sums[PL_SUM_TILES_DRAG_CLOSED]));
                results[i] = detail::finishBuoyancy(
                    sums, requests[i].frame.pose.apply(body.centerOfMass), requests[i].fluid);
            }
        } catch (const cl::Error& e) {
            drainQueue();
            return makeError(ErrorKind::device, name_ + ": " + clError(e));
        } catch (const std::length_error& e) {  // a buffer beyond the device's limits
            drainQueue();
            return makeError(ErrorKind::limit, name_ + ": " + e.what());
        }
        timings_.totalMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        return Ok{};
    }

    FrameTimings lastTimings() const override { return timings_; }

    TileCounts lastTileCounts() const override { return tileCounts_; }

    std::size_t addExchangeSet(std::span<const ExchangeSample> samples,
                               std::size_t nodes) override {
        // Sorted by node (a work-group then spans few nodes), positions relative to the
        // samples' centroid so single precision keeps its digits.
        ExchangeSet set;
        set.nodes = nodes;
        set.count = samples.size();
        for (const ExchangeSample& x : samples) set.centre += x.position;
        if (!samples.empty()) set.centre /= static_cast<double>(samples.size());
        std::vector<std::size_t> order(samples.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return samples[a].node < samples[b].node;
        });
        std::vector<pl_float4> points;
        std::vector<cl_uint> nodeOf;
        for (std::size_t i : order) {
            points.push_back(toFloat4(samples[i].position - set.centre, samples[i].weight));
            nodeOf.push_back(samples[i].node);
        }
        set.samples = upload(points);
        set.nodeOf = upload(nodeOf);
        const std::size_t groups = (set.count + PL_WORKGROUP_SIZE - 1) / PL_WORKGROUP_SIZE;
        const std::size_t accSize = fp64_ ? sizeof(double) : sizeof(float);
        set.partialsHost.assign(std::max<std::size_t>(1, groups * nodes * 3) * accSize, 0);
        set.partials = cl::Buffer(context_, CL_MEM_WRITE_ONLY, set.partialsHost.size());
        set.surfaces =
            cl::Buffer(context_, CL_MEM_READ_ONLY, std::max<std::size_t>(1, nodes) * sizeof(float));
        exchangeSets_.push_back(std::move(set));
        return exchangeSets_.size() - 1;
    }

    Status evaluateExchange(std::size_t id, const ExchangeFrame& frame, const WaterModel& water,
                            ExchangeSums& sums) override {
        if (id >= exchangeSets_.size())
            return makeError(ErrorKind::invalidArgument, "evaluateExchange: unknown set id");
        ExchangeSet& set = exchangeSets_[id];
        sums.inflow.assign(set.nodes, 0.0);
        sums.outflow.assign(set.nodes, 0.0);
        sums.outsideTop.assign(set.nodes, -std::numeric_limits<double>::infinity());
        if (set.count == 0 || set.nodes == 0) return Ok{};
        if (frame.nodeSurface.size() != set.nodes) {
            return makeError(ErrorKind::invalidArgument,
                             "evaluateExchange: " + std::to_string(frame.nodeSurface.size()) +
                                 " node surfaces for " + std::to_string(set.nodes) + " nodes");
        }
        try {
            // The frame relative to c, the samples' centre in the world.
            const Eigen::Vector3d c = frame.pose.apply(set.centre);
            gpu::PlBody p{};
            for (int k = 0; k < 3; ++k) {
                p.rotation[k] = toFloat4(frame.pose.rotation.row(k).transpose());
            }
            std::array<gpu::PlWave, PL_MAX_WAVES> waves{};
            fillWater(p, water, c, frame.time, waves.data());
            p.waveBegin = 0;
            std::vector<float> surfaces(set.nodes);
            for (std::size_t n = 0; n < set.nodes; ++n) {
                const double s = frame.nodeSurface[n] - c.y();
                surfaces[n] = std::isfinite(s) ? static_cast<float>(s) : -3e38f;
            }
            if (!exchangeFrame_()) {
                exchangeFrame_ = cl::Buffer(context_, CL_MEM_READ_ONLY, sizeof(gpu::PlBody));
                exchangeWaves_ =
                    cl::Buffer(context_, CL_MEM_READ_ONLY, PL_MAX_WAVES * sizeof(gpu::PlWave));
            }
            if (water.kind == WaterModel::Kind::HeightField)
                uploadGrid(water.grid);
            else if (!gridBuffer_())
                gridBuffer_ = cl::Buffer(context_, CL_MEM_READ_ONLY, sizeof(float));
            queue_.enqueueWriteBuffer(exchangeFrame_, CL_FALSE, 0, sizeof(gpu::PlBody), &p);
            queue_.enqueueWriteBuffer(exchangeWaves_, CL_FALSE, 0,
                                      PL_MAX_WAVES * sizeof(gpu::PlWave), waves.data());
            queue_.enqueueWriteBuffer(set.surfaces, CL_FALSE, 0, set.nodes * sizeof(float),
                                      surfaces.data());
            const int model = water.kind == WaterModel::Kind::Gerstner      ? 1
                              : water.kind == WaterModel::Kind::HeightField ? 2
                                                                            : 0;
            cl::Kernel& kernel = exchangeKernels_[model];
            kernel.setArg(0, set.samples);
            kernel.setArg(1, set.nodeOf);
            kernel.setArg(2, static_cast<cl_uint>(set.count));
            kernel.setArg(3, exchangeFrame_);
            kernel.setArg(4, exchangeWaves_);
            kernel.setArg(5, gridBuffer_);
            kernel.setArg(6, static_cast<cl_int>(std::max(1, gridCountX_)));
            kernel.setArg(7, static_cast<cl_int>(std::max(1, gridCountZ_)));
            kernel.setArg(8, set.surfaces);
            // The exchange's lattice about c (plimsoll_eval exchangeSurfaces): c's place in its
            // cell worked out in double, the samples' offsets in single precision.
            const double spacing = plimsoll_eval::kExchangeLatticeSpacing;
            const double lx = c.x() / spacing, lz = c.z() / spacing;
            const cl_float4 lattice = {{static_cast<cl_float>(lx - std::floor(lx)),
                                        static_cast<cl_float>(lz - std::floor(lz)),
                                        static_cast<cl_float>(1.0 / spacing),
                                        static_cast<cl_float>(spacing)}};
            kernel.setArg(9, lattice);
            kernel.setArg(10, static_cast<cl_float>(frame.factor));
            kernel.setArg(11, static_cast<cl_int>(frame.torricelli ? 1 : 0));
            kernel.setArg(12, static_cast<cl_uint>(set.nodes));
            kernel.setArg(13, set.partials);
            const std::size_t groups = (set.count + PL_WORKGROUP_SIZE - 1) / PL_WORKGROUP_SIZE;
            faultPoint(detail::OpenClFault::Launch, "clEnqueueNDRangeKernel");
            queue_.enqueueNDRangeKernel(kernel, cl::NullRange,
                                        cl::NDRange(groups * PL_WORKGROUP_SIZE),
                                        cl::NDRange(PL_WORKGROUP_SIZE));
            queue_.enqueueReadBuffer(set.partials, CL_TRUE, 0, set.partialsHost.size(),
                                     set.partialsHost.data());
            // The groups' partials, summed in double.
            for (std::size_t g = 0; g < groups; ++g) {
                for (std::size_t n = 0; n < set.nodes; ++n) {
                    const std::size_t at = (g * set.nodes + n) * 3;
                    auto value = [&](std::size_t k) {
                        return fp64_ ? reinterpret_cast<const double*>(
                                           set.partialsHost.data())[at + k]
                                     : static_cast<double>(reinterpret_cast<const float*>(
                                           set.partialsHost.data())[at + k]);
                    };
                    sums.inflow[n] += value(0);
                    sums.outflow[n] += value(1);
                    if (value(0) > 0)
                        sums.outsideTop[n] = std::max(sums.outsideTop[n], value(2) + c.y());
                }
            }
        } catch (const cl::Error& e) {
            drainQueue();
            return makeError(ErrorKind::device, name_ + ": " + clError(e));
        }
        return Ok{};
    }

private:
    /// A water graph's permeable samples on the device.
    struct ExchangeSet {
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< object space, m
        std::size_t count = 0, nodes = 0;
        cl::Buffer samples, nodeOf, surfaces, partials;
        std::vector<unsigned char> partialsHost;
    };

    struct Body {
        Eigen::Vector3d centerOfMass;
        std::size_t firstEntry = 0;         ///< in positions_ / areaVectors_
        std::vector<std::uint32_t> order;   ///< texture entry of each device entry
        std::vector<std::size_t> tileEnds;  ///< end (in `order`) of each of its tiles
        std::uint32_t tileBegin = 0, tileEnd = 0;
        std::uint32_t chunkBegin = 0, chunkEnd = 0;  ///< in chunks_: its tiles' sums
        double radius = 0;  ///< largest distance of an entry from c (m): the tolerances' scale
    };

    /// Writes a body's entries, tiles and tile moments into the host arrays.
    void fillBody(std::size_t id, const SurfaceTextures& textures) {
        Body& body = bodies_[id];
        body.radius = 0;
        for (std::size_t k = 0; k < body.order.size(); ++k) {
            const std::uint32_t i = body.order[k];
            positions_[body.firstEntry + k] =
                toFloat4(textures.position[i] - body.centerOfMass, textures.area[i]);
            areaVectors_[body.firstEntry + k] = toFloat4(textures.areaVector[i]);
            body.radius = std::max(body.radius, (textures.position[i] - body.centerOfMass).norm());
        }
        std::size_t begin = 0;
        for (std::size_t t = 0; t < body.tileEnds.size(); ++t) {
            const std::size_t end = body.tileEnds[t];
            gpu::PlTile& tile = tiles_[body.tileBegin + t];
            tile = tileOf(static_cast<std::uint32_t>(id), body.firstEntry + begin,
                          body.firstEntry + end);
            const Eigen::Vector3d centre(tile.sphere.x, tile.sphere.y, tile.sphere.z);
            tileMoments_[body.tileBegin + t] =
                momentsOf(textures, body.centerOfMass + centre,
                          std::span(body.order).subspan(begin, end - begin));
            begin = end;
        }
    }

    gpu::PlTile tileOf(std::uint32_t body, std::size_t begin, std::size_t end) const {
        Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e30f), hi = -lo;
        for (std::size_t i = begin; i < end; ++i) {
            const Eigen::Vector3f p(positions_[i].x, positions_[i].y, positions_[i].z);
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
        const Eigen::Vector3f centre = 0.5f * (lo + hi);
        // Entries count as partly wet up to half their extent above the surface (wetShare).
        float radius = 0;
        for (std::size_t i = begin; i < end; ++i) {
            const Eigen::Vector3f p(positions_[i].x, positions_[i].y, positions_[i].z);
            radius = std::max(radius, (p - centre).norm() + 0.5f * std::sqrt(positions_[i].w));
        }
        // Slack for the kernel's single-precision rotation of the centre.
        radius = radius * (1.0f + 1e-5f) + 1e-6f * centre.norm();
        // The cone of the normals: about their mean direction, its cosine the smallest over
        // the entries (shaved by a rounding margin, so that the kernel's sign test holds).
        Eigen::Vector3d axis = Eigen::Vector3d::Zero();
        for (std::size_t i = begin; i < end; ++i) {
            const Eigen::Vector3d a(areaVectors_[i].x, areaVectors_[i].y, areaVectors_[i].z);
            if (a.norm() > 0) axis += a.normalized();
        }
        double cosSpread = -1;
        if (axis.norm() > 0) {
            axis.normalize();
            cosSpread = 1;
            for (std::size_t i = begin; i < end; ++i) {
                const Eigen::Vector3d a(areaVectors_[i].x, areaVectors_[i].y, areaVectors_[i].z);
                if (a.norm() > 0) cosSpread = std::min(cosSpread, axis.dot(a.normalized()));
            }
            cosSpread -= 1e-5;
        }
        gpu::PlTile tile{};
        tile.body = body;
        tile.begin = static_cast<std::uint32_t>(begin);
        tile.end = static_cast<std::uint32_t>(end);
        tile.sphere = {centre.x(), centre.y(), centre.z(), radius};
        tile.cone = {static_cast<float>(axis.x()), static_cast<float>(axis.y()),
                     static_cast<float>(axis.z()), static_cast<float>(cosSpread)};
        return tile;
    }

    /// Side of a square block of texels holding about one tile.
    static std::uint32_t blockSideFor(std::size_t tileSize) {
        return static_cast<std::uint32_t>(std::max(1.0, std::floor(std::sqrt(double(tileSize)))));
    }

    static std::uint32_t blockOf(std::uint32_t texel, int size, std::uint32_t side) {
        const std::uint32_t n = static_cast<std::uint32_t>(size);
        const std::uint32_t blocksPerRow = (n + side - 1) / side;
        return (texel / n / side) * blocksPerRow + (texel % n) / side;
    }

    /// Entries sorted by block (stable: row-major within a block).
    std::vector<std::uint32_t> blockOrder(const SurfaceTextures& textures) const {
        std::vector<std::uint32_t> order(textures.coveredCount());
        for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
        const std::uint32_t side = blockSideFor(tileSize_);
        std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
            return blockOf(textures.texelIndex[a], textures.size, side) <
                   blockOf(textures.texelIndex[b], textures.size, side);
        });
        return order;
    }

    /// The moments of the given entries' area vectors about `centre` (object space, as
    /// textures.position), in double, rounded once: PlTileMoments.
    static gpu::PlTileMoments momentsOf(const SurfaceTextures& textures,
                                        const Eigen::Vector3d& centre,
                                        std::span<const std::uint32_t> entries) {
        double n0[3] = {}, n1[3][3] = {}, n2[3][6] = {}, n3[3][10] = {};
        double area = 0;
        for (std::uint32_t e : entries) {
            const Eigen::Vector3d s = textures.position[e] - centre;
            const Eigen::Vector3d& a = textures.areaVector[e];
            area += textures.area[e];
            for (int i = 0; i < 3; ++i) {
                n0[i] += a[i];
                for (int j = 0; j < 3; ++j) {
                    n1[i][j] += a[i] * s[j];
                    for (int k = j; k < 3; ++k) {
                        n2[i][plimsoll_eval::kPair[j][k]] += a[i] * s[j] * s[k];
                        for (int l = k; l < 3; ++l)
                            n3[i][plimsoll_eval::kTriple[j][k][l]] += a[i] * s[j] * s[k] * s[l];
                    }
                }
            }
        }
        gpu::PlTileMoments m{};
        m.sum = toFloat4(Eigen::Vector3d(n0[0], n0[1], n0[2]), area);
        for (int i = 0; i < 3; ++i)
            m.first[i] = toFloat4(Eigen::Vector3d(n1[i][0], n1[i][1], n1[i][2]));
        m.first[0].w = static_cast<float>(entries.size());
        for (int i = 0; i < 3; ++i) {
            for (int k = 0; k < 6; ++k) m.second[6 * i + k] = static_cast<float>(n2[i][k]);
            for (int k = 0; k < 10; ++k) m.third[10 * i + k] = static_cast<float>(n3[i][k]);
        }
        return m;
    }

    /// Every device buffer is made here: checked against the device's limits first, so an
    /// oversized body is an error naming the buffer, its size and the limit, not a failure
    /// deep in the driver.
    cl::Buffer makeBuffer(cl_mem_flags flags, std::size_t bytes, void* host, const char* what) {
        const cl_ulong maxAlloc = testMaxAlloc.load()
                                      ? testMaxAlloc.load()
                                      : device_.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
        if (bytes > maxAlloc) {
            throw std::length_error(std::string(what) + " buffer of " + formatBytes(double(bytes)) +
                                    " is more than the device's CL_DEVICE_MAX_MEM_ALLOC_SIZE (" +
                                    formatBytes(double(maxAlloc)) + ")");
        }
        faultPoint(detail::OpenClFault::BufferAllocation, "clCreateBuffer");
        return cl::Buffer(context_, flags, bytes, host);
    }

    /// The data as a read-only buffer. An empty vector (a body sealed everywhere has no
    /// permeable samples) gets one zero element: OpenCL refuses a buffer of size 0, and a copy
    /// from the null pointer an empty vector's data() may be (CL_INVALID_HOST_PTR).
    template <class T>
    cl::Buffer upload(const std::vector<T>& data, const char* what = "input") {
        if (data.empty()) {
            T zero{};
            return makeBuffer(CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(T), &zero, what);
        }
        return makeBuffer(CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, data.size() * sizeof(T),
                          const_cast<T*>(data.data()), what);
    }

    /// Creates every buffer for the current set of bodies; evaluate() only writes into them.
    void rebuildBuffers() {
        const std::size_t accSize = fp64_ ? sizeof(double) : sizeof(float);
        // The whole set must fit the device's memory: checked before anything is allocated.
        const double total =
            double(positions_.size() + areaVectors_.size()) * sizeof(pl_float4) +
            double(tiles_.size()) *
                (sizeof(gpu::PlTile) + sizeof(gpu::PlTileMoments) + PL_SUM_SLOTS * accSize);
        const cl_ulong globalMemory = testGlobalMemory.load()
                                          ? testGlobalMemory.load()
                                          : device_.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
        if (total > double(globalMemory)) {
            throw std::length_error("the bodies' buffers need " + formatBytes(total) +
                                    ", more than the device's CL_DEVICE_GLOBAL_MEM_SIZE (" +
                                    formatBytes(double(globalMemory)) + ")");
        }
        positionsBuffer_ = upload(positions_, "positions");
        areaVectorsBuffer_ = upload(areaVectors_, "area vectors");
        tilesBuffer_ = upload(tiles_, "tiles");
        tileMomentsBuffer_ = upload(tileMoments_, "tile moments");
        allocateFrameParams();
        partialsBuffer_ =
            cl::Buffer(context_, CL_MEM_READ_WRITE,
                       std::max<std::size_t>(1, tiles_.size()) * PL_SUM_SLOTS * accSize);
        // The second launch sums each body's tile partials in chunks of kTilesPerChunk, one
        // work-group each, and the host adds a body's chunks: one group for all of a 2048^2
        // body's 4096 tiles took 43 us on an H200, most of a frame.
        // Every body gets at least one chunk (an empty one, summing to 0, where it has no
        // tiles): the second launch is never of size 0, which OpenCL refuses, while a body is.
        chunks_.clear();
        for (Body& body : bodies_) {
            body.chunkBegin = static_cast<std::uint32_t>(chunks_.size());
            std::uint32_t t = body.tileBegin;
            do {
                const std::uint32_t end = std::min<std::uint32_t>(body.tileEnd, t + kTilesPerChunk);
                chunks_.push_back({{t, end}});
                t = end;
            } while (t < body.tileEnd);
            body.chunkEnd = static_cast<std::uint32_t>(chunks_.size());
        }
        chunksBuffer_ = upload(chunks_, "chunks");
        totalsBuffer_ =
            cl::Buffer(context_, CL_MEM_WRITE_ONLY,
                       std::max<std::size_t>(1, chunks_.size()) * PL_SUM_SLOTS * accSize);
        totalsHost_.allocate(context_, queue_,
                             std::max<std::size_t>(1, chunks_.size()) * PL_SUM_SLOTS * accSize);
        gridHeights_.clear();
        gridBuffer_ = cl::Buffer(context_, CL_MEM_READ_ONLY, sizeof(float));
        buffersStale_ = false;
    }

    /// The frame's parameter block and its device buffer, for bodies_.size() bodies. The waves'
    /// offset is a multiple of CL_DEVICE_MEM_BASE_ADDR_ALIGN, where a sub-buffer may begin.
    /// One write instead of two saves a command on every frame on waves (about 2 us of an
    /// H200's 57-60 us for one body of 2048^2; docs/design.md).
    void allocateFrameParams() {
        const std::size_t count = std::max<std::size_t>(1, bodies_.size());
        const std::size_t align = std::max<std::size_t>(
            alignof(gpu::PlWave), device_.getInfo<CL_DEVICE_MEM_BASE_ADDR_ALIGN>() / 8);
        bodiesBytes_ = count * sizeof(gpu::PlBody);
        wavesOffset_ = (bodiesBytes_ + align - 1) / align * align;
        const std::size_t wavesBytes = count * PL_MAX_WAVES * sizeof(gpu::PlWave);
        frameParams_.allocate(context_, queue_, wavesOffset_ + wavesBytes);
        frameBuffer_ = cl::Buffer(context_, CL_MEM_READ_ONLY, frameParams_.size());
        cl_buffer_region bodies{0, bodiesBytes_}, waves{wavesOffset_, wavesBytes};
        bodiesBuffer_ =
            frameBuffer_.createSubBuffer(CL_MEM_READ_ONLY, CL_BUFFER_CREATE_TYPE_REGION, &bodies);
        wavesBuffer_ =
            frameBuffer_.createSubBuffer(CL_MEM_READ_ONLY, CL_BUFFER_CREATE_TYPE_REGION, &waves);
    }

    gpu::PlBody* bodyParams() { return reinterpret_cast<gpu::PlBody*>(frameParams_.data()); }
    gpu::PlWave* waveParams() {
        return reinterpret_cast<gpu::PlWave*>(frameParams_.data() + wavesOffset_);
    }

    /// Fills the per-frame parameters: every body relative to its own centre of mass, in
    /// double on the host, then rounded (so a body 1e5 m away keeps millimetres).
    Status prepareFrame(std::span<const BodyRequest> requests, const WaterModel& water) {
        for (std::size_t b = 0; b < bodies_.size(); ++b) {
            gpu::PlBody& p = bodyParams()[b];
            p = gpu::PlBody{};
            p.water = {0.0f, -3e38f, 0.0f, 0.0f};  // not requested: every tile is culled
        }
        if (water.kind == WaterModel::Kind::HeightField) uploadGrid(water.grid);
        for (const BodyRequest& request : requests) {
            if (request.body >= bodies_.size())
                return makeError(ErrorKind::invalidArgument, "evaluate: unknown body id");
            const Body& body = bodies_[request.body];
            const BodyFrame& frame = request.frame;
            const Eigen::Vector3d c = frame.pose.apply(body.centerOfMass);
            gpu::PlBody& p = bodyParams()[request.body];
            for (int k = 0; k < 3; ++k)
                p.rotation[k] = toFloat4(frame.pose.rotation.row(k).transpose());
            p.velocity = toFloat4(frame.motion.linear);
            p.spin = toFloat4(frame.motion.angular);
            const FluidSettings& fluid = request.fluid;
            p.fluid = {static_cast<float>(fluid.density * fluid.gravity),
                       static_cast<float>(0.5 * fluid.density * fluid.dragCoefficient),
                       static_cast<float>(0.5 * fluid.density * fluid.frictionCoefficient),
                       static_cast<float>(fluid.density)};
            p.waveBegin = static_cast<gpu::pl_int>(request.body * PL_MAX_WAVES);
            fillWater(p, water, c, frame.time, &waveParams()[p.waveBegin]);
            if (water.kind != WaterModel::Kind::Flat)
                p.water.z = static_cast<float>(options_.waveTolerance * body.radius);
        }
        return Ok{};
    }

    /// The water model as seen from a point c (world): model, level, waves or grid cell.
    void fillWater(gpu::PlBody& p, const WaterModel& water, const Eigen::Vector3d& c, double time,
                   gpu::PlWave* waves) {
        p.water = {static_cast<float>(water.level - c.y()),
                   static_cast<float>(water.maxHeight() - c.y()), 0.0f, 0.0f};
        switch (water.kind) {
            case WaterModel::Kind::Flat:
                p.waterModel = PL_WATER_FLAT;
                break;
            case WaterModel::Kind::Gerstner:
                p.waterModel = PL_WATER_GERSTNER;
                p.waveCount = fillWaves(water, c, time, waves);
                break;
            case WaterModel::Kind::HeightField: {
                p.waterModel = PL_WATER_HEIGHTFIELD;
                const double gx = (c.x() - water.grid.origin.x()) / water.grid.spacing;
                const double gz = (c.z() - water.grid.origin.y()) / water.grid.spacing;
                // Beyond the grid every cell index clamps to the edge anyway.
                const double cellX = std::clamp(std::floor(gx), -1e6, 1e6);
                const double cellZ = std::clamp(std::floor(gz), -1e6, 1e6);
                p.gridCellX = static_cast<gpu::pl_int>(cellX);
                p.gridCellZ = static_cast<gpu::pl_int>(cellZ);
                p.grid = {static_cast<float>(std::clamp(gx - cellX, -1e6, 1e6)),
                          static_cast<float>(std::clamp(gz - cellZ, -1e6, 1e6)),
                          static_cast<float>(1.0 / water.grid.spacing), 0.0f};
                break;
            }
        }
    }

    int fillWaves(const WaterModel& water, const Eigen::Vector3d& c, double time,
                  gpu::PlWave* waves) {
        const int count = std::min<int>(PL_MAX_WAVES, static_cast<int>(water.waves.size()));
        for (int w = 0; w < count; ++w) {
            const GerstnerWave& wave = water.waves[w];
            const double k = 2.0 * std::numbers::pi / wave.wavelength;
            const double omega = std::sqrt(water.gravity * k);
            const double n = wave.direction.norm();
            const Eigen::Vector2d d =
                n > 0 ? Eigen::Vector2d(wave.direction / n) : Eigen::Vector2d(1.0, 0.0);
            // The phase at the centre of mass, in double and reduced, so float keeps it.
            const double phase =
                std::remainder(k * (d.x() * c.x() + d.y() * c.z()) - omega * time + wave.phase,
                               2.0 * std::numbers::pi);
            gpu::PlWave& out = waves[w];
            out.amplitude = static_cast<float>(wave.amplitude);
            out.wavenumber = static_cast<float>(k);
            out.omega = static_cast<float>(omega);
            out.q = static_cast<float>(
                wave.amplitude > 0 ? wave.steepness / (k * wave.amplitude *
                                                       static_cast<double>(water.waves.size()))
                                   : 0.0);
            out.directionX = static_cast<float>(d.x());
            out.directionZ = static_cast<float>(d.y());
            out.phase = static_cast<float>(phase);
        }
        return count;
    }

    void uploadGrid(const HeightGrid& grid) {
        if (grid.heights == gridHeights_ && gridCountX_ == grid.countX) return;
        gridHeights_ = grid.heights;
        gridCountX_ = grid.countX;
        gridCountZ_ = grid.countZ;
        gridBuffer_ = upload(gridHeights_);
    }

    /// The kernel variant for this frame's water, without drag when nothing moves.
    cl::Kernel& tilesKernelFor(std::span<const BodyRequest> requests, const WaterModel& water) {
        const int model = water.kind == WaterModel::Kind::Gerstner      ? 1
                          : water.kind == WaterModel::Kind::HeightField ? 2
                                                                        : 0;
        bool still = water.kind != WaterModel::Kind::Gerstner;
        for (const BodyRequest& r : requests)
            still = still && r.frame.motion.linear.isZero() && r.frame.motion.angular.isZero();
        return tilesKernels_[model][still ? 1 : 0];
    }

    /// One frame: the bodies' parameters (and the waves, which only the Gerstner kernels read:
    /// PL_MAX_WAVES per body, 256 kB a frame for 1000 bodies) up, the two launches, the totals
    /// back. Events are asked for only where they are read: for the timings, and for the read
    /// when the wait spins.
    void runFrame(cl::Kernel& tilesKernel, bool withWaves) {
        const bool timed = options_.deviceTimings;
        cl::Event writeParams, tilesDone, reduceDone, readTotals;
        // One write, of the waves too where the kernel reads them (they lie after the bodies).
        queue_.enqueueWriteBuffer(frameBuffer_, CL_FALSE, 0,
                                  withWaves ? frameParams_.size() : bodiesBytes_,
                                  frameParams_.data(), nullptr, timed ? &writeParams : nullptr);
        tilesKernel.setArg(0, positionsBuffer_);
        tilesKernel.setArg(1, areaVectorsBuffer_);
        tilesKernel.setArg(2, tilesBuffer_);
        tilesKernel.setArg(3, tileMomentsBuffer_);
        tilesKernel.setArg(4, bodiesBuffer_);
        tilesKernel.setArg(5, wavesBuffer_);
        tilesKernel.setArg(6, gridBuffer_);
        tilesKernel.setArg(7, static_cast<cl_int>(std::max(1, gridCountX_)));
        tilesKernel.setArg(8, static_cast<cl_int>(std::max(1, gridCountZ_)));
        tilesKernel.setArg(9, partialsBuffer_);
        faultPoint(detail::OpenClFault::Launch, "clEnqueueNDRangeKernel");
        if (!tiles_.empty()) {
            queue_.enqueueNDRangeKernel(
                tilesKernel, cl::NullRange, cl::NDRange(tiles_.size() * PL_WORKGROUP_SIZE),
                cl::NDRange(PL_WORKGROUP_SIZE), nullptr, timed ? &tilesDone : nullptr);
        }
        reduceKernel_.setArg(0, partialsBuffer_);
        reduceKernel_.setArg(1, chunksBuffer_);
        reduceKernel_.setArg(2, totalsBuffer_);
        queue_.enqueueNDRangeKernel(
            reduceKernel_, cl::NullRange, cl::NDRange(chunks_.size() * PL_WORKGROUP_SIZE),
            cl::NDRange(PL_WORKGROUP_SIZE), nullptr, timed ? &reduceDone : nullptr);
        faultPoint(detail::OpenClFault::LostDevice, "clEnqueueReadBuffer");
        queue_.enqueueReadBuffer(totalsBuffer_, spinWait_ ? CL_FALSE : CL_TRUE, 0,
                                 totalsHost_.size(), totalsHost_.data(), nullptr,
                                 timed || spinWait_ ? &readTotals : nullptr);
        if (spinWait_) spinUntilComplete(readTotals);
        if (!timed) return;
        timings_.uploadMs = eventMs(writeParams);
        timings_.reduceMs = eventMs(reduceDone);
        timings_.kernelMs = (tiles_.empty() ? 0.0 : eventMs(tilesDone)) + timings_.reduceMs;
        timings_.readbackMs = eventMs(readTotals);
    }

    /// OpenClWait::spin: the queue is flushed and the read's status polled until it is
    /// complete (or failed), so the thread never sleeps on the driver; then one clWaitForEvents,
    /// which returns at once but is the synchronisation point that the status query is not
    /// (and throws where the read failed).
    void spinUntilComplete(const cl::Event& read) {
        queue_.flush();
        while (read.getInfo<CL_EVENT_COMMAND_EXECUTION_STATUS>() > CL_COMPLETE) {
#if defined(__x86_64__) || defined(__i386__)
            __builtin_ia32_pause();
#endif
        }
        read.wait();
    }

    cl::Device device_;
    cl::Context context_;
    cl::CommandQueue queue_;
    cl::Program program_;
    std::array<std::array<cl::Kernel, 2>, 3> tilesKernels_;  ///< [water model][still]
    cl::Kernel reduceKernel_;
    std::array<cl::Kernel, 3> exchangeKernels_;  ///< [water model]
    bool fp64_;
    std::size_t tileSize_;  ///< entries per tile: PL_WORKGROUP_SIZE x items per thread
    OpenClOptions options_;
    TileCounts tileCounts_;
    std::string name_;
    BackendKind kind_;
    bool spinWait_;  ///< OpenClOptions::wait, resolved for this device

    std::vector<Body> bodies_;
    std::vector<pl_float4> positions_, areaVectors_;
    std::vector<gpu::PlTile> tiles_;
    std::vector<gpu::PlTileMoments> tileMoments_;
    bool buffersStale_ = true;
    cl::Buffer positionsBuffer_, areaVectorsBuffer_, tilesBuffer_, tileMomentsBuffer_,
        bodiesBuffer_, wavesBuffer_, gridBuffer_, partialsBuffer_, totalsBuffer_, chunksBuffer_;
    std::vector<cl_uint2> chunks_;  ///< tile ranges [s[0], s[1]) the second launch sums
    /// The frame's parameters, in one block so that a frame uploads them in one write: the
    /// bodies from 0, then the waves (PL_MAX_WAVES a body) from wavesOffset_. frameBuffer_ is
    /// its device copy; bodiesBuffer_ and wavesBuffer_ are sub-buffers of it, what the
    /// kernels take.
    PinnedBytes frameParams_;
    cl::Buffer frameBuffer_;
    std::size_t bodiesBytes_ = 0, wavesOffset_ = 0;
    PinnedBytes totalsHost_;
    std::vector<float> gridHeights_;
    int gridCountX_ = 0, gridCountZ_ = 0;
    FrameTimings timings_;
    std::vector<ExchangeSet> exchangeSets_;
    cl::Buffer exchangeFrame_, exchangeWaves_;
};

bool deviceHasFp64(const cl::Device& device) {
    return device.getInfo<CL_DEVICE_EXTENSIONS>().find("cl_khr_fp64") != std::string::npos;
}

/// Entries per work-item: the group's reduction of all slots in local memory costs about as
/// much as a few entries, so each work-item takes several. 8 was fastest on PoCL (2 cores:
/// 3.0 ms against 10 ms with one entry per work-item, 1024^2 texels, 10 sums).
int itemsPerThreadFor(const cl::Device&) { return 8; }

}  // namespace

bool openClAvailable() { return true; }

std::vector<ComputeDevice> listComputeDevices() {
    std::vector<ComputeDevice> out;
    const std::vector<DeviceHandle> handles = enumerateDevices();
    for (std::size_t i = 0; i < handles.size(); ++i) {
        const cl::Device& d = handles[i].device;
        ComputeDevice info;
        info.index = static_cast<int>(i);
        info.platform = handles[i].platform.getInfo<CL_PLATFORM_NAME>();
        info.name = d.getInfo<CL_DEVICE_NAME>();
        info.isGpu = (d.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_GPU) != 0;
        info.hasFp64 = deviceHasFp64(d);
        info.globalMemory = d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
        out.push_back(info);
    }
    return out;
}

namespace detail {

void failOpenClCallsForTesting(OpenClFault kind, int count) {
    injectedFaults[static_cast<int>(kind)] = std::max(0, count);
}

void setOpenClMemoryLimitsForTesting(std::uint64_t maxAllocation, std::uint64_t globalMemory) {
    testMaxAlloc = maxAllocation;
    testGlobalMemory = globalMemory;
}

Result<std::unique_ptr<BuoyancyBackend>> createOpenClBackend(int index,
                                                             const OpenClOptions& options) {
    const std::vector<DeviceHandle> handles = enumerateDevices();
    if (index < 0 || index >= static_cast<int>(handles.size())) {
        return makeError(ErrorKind::device, "no OpenCL device " + std::to_string(index));
    }
    try {
        const DeviceHandle& handle = handles[index];
        cl::Context context(handle.device);
        const bool fp64 = deviceHasFp64(handle.device);
        if (options.itemsPerThread < 0 || options.itemsPerThread > kMaxOpenClItemsPerThread) {
            return makeError(ErrorKind::invalidArgument,
                             "OpenCL items per thread must be 0 (the device's default) to " +
                                 std::to_string(kMaxOpenClItemsPerThread) + ", not " +
                                 std::to_string(options.itemsPerThread));
        }
        const int items =
            options.itemsPerThread > 0 ? options.itemsPerThread : itemsPerThreadFor(handle.device);
        Result<cl::Program> program = buildProgram(context, handle.device, fp64, items);
        if (!program) return program.error();
        return std::unique_ptr<BuoyancyBackend>(std::make_unique<OpenClBackend>(
            handle, context, std::move(*program), fp64, items * PL_WORKGROUP_SIZE, options));
    } catch (const cl::Error& e) {
        return makeError(ErrorKind::device, clError(e));
    }
}

Status compileKernelSource(int index, const std::string& source) {
    const std::vector<DeviceHandle> handles = enumerateDevices();
    if (index < 0 || index >= static_cast<int>(handles.size())) {
        return makeError(ErrorKind::device, "no OpenCL device " + std::to_string(index));
    }
    try {
        const cl::Device& device = handles[index].device;
        cl::Context context(device);
        Result<cl::Program> program =
            buildProgram(context, device, deviceHasFp64(device), itemsPerThreadFor(device), source);
        if (!program) return program.error();
        return Ok{};
    } catch (const cl::Error& e) {
        return makeError(ErrorKind::device, clError(e));
    }
}

}  // namespace detail

Result<double> measureCopyBandwidth(const std::string& spec, std::size_t bytes) {
    std::vector<DeviceHandle> handles = enumerateDevices();
    int index = -1;
    for (std::size_t i = 0; i < handles.size(); ++i) {
        const bool gpu = (handles[i].device.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_GPU) != 0;
        if (spec == std::to_string(i) || (spec == "gpu" && gpu) || (spec == "cpu" && !gpu)) {
            index = static_cast<int>(i);
            break;
        }
    }
    if (index < 0)
        return makeError(ErrorKind::device, "no OpenCL device '" + spec + "' to measure");
    try {
        const cl::Device& device = handles[index].device;
        cl::Context context(device);
        Result<cl::Program> program =
            buildProgram(context, device, deviceHasFp64(device), itemsPerThreadFor(device));
        if (!program) return program.error();
        cl::CommandQueue queue(context, device, CL_QUEUE_PROFILING_ENABLE);
        cl::Kernel copy(*program, "copy_float4");
        const std::size_t count = bytes / sizeof(pl_float4);
        cl::Buffer source(context, CL_MEM_READ_WRITE, count * sizeof(pl_float4));
        cl::Buffer target(context, CL_MEM_READ_WRITE, count * sizeof(pl_float4));
        queue.enqueueFillBuffer(source, 1.0f, 0, count * sizeof(pl_float4));
        copy.setArg(0, source);
        copy.setArg(1, target);
        std::vector<double> ms;
        for (int run = 0; run < 12; ++run) {
            cl::Event done;
            queue.enqueueNDRangeKernel(copy, cl::NullRange, cl::NDRange(count), cl::NullRange,
                                       nullptr, &done);
            done.wait();
            if (run >= 2) ms.push_back(eventMs(done));  // the first runs warm up
        }
        std::sort(ms.begin(), ms.end());
        const double median = ms[ms.size() / 2];
        return 2.0 * static_cast<double>(count * sizeof(pl_float4)) / (median * 1e-3) / 1e9;
    } catch (const cl::Error& e) {
        return makeError(ErrorKind::device, clError(e));
    }
}

}  // namespace plimsoll
