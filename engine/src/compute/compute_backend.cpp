// Backend choice and the C++ reference backend.
#include "plimsoll/bake/bake.h"
#include "plimsoll/compute/compute.h"
#include "plimsoll/compute/fast_backend.h"

#include "compute/opencl_backend.h"

#include <chrono>
#include <cstdlib>

namespace plimsoll {

namespace {

class ReferenceBackend final : public BuoyancyBackend {
public:
    BackendKind kind() const override { return BackendKind::reference; }
    std::string deviceName() const override { return "reference (C++)"; }

    std::size_t addBody(const SurfaceTextures& textures,
                        const Eigen::Vector3d& centerOfMass) override {
        bodies_.push_back({textures, centerOfMass});
        return bodies_.size() - 1;
    }

    Status updateBody(std::size_t id, const SurfaceTextures& textures,
                      const Eigen::Vector3d& centerOfMass) override {
        if (id >= bodies_.size())
            return makeError(ErrorKind::invalidArgument, "updateBody: unknown body id");
        bodies_[id] = {textures, centerOfMass};
        return Ok{};
    }

    Status evaluate(std::span<const BodyRequest> requests, const WaterModel& water,
                    std::span<BuoyancyResult> results) override {
        const auto start = std::chrono::steady_clock::now();
        for (std::size_t i = 0; i < requests.size(); ++i) {
            const BodyRequest& request = requests[i];
            if (request.body >= bodies_.size())
                return makeError(ErrorKind::invalidArgument, "evaluate: unknown body id");
            BodyFrame frame = request.frame;
            frame.centerOfMass = bodies_[request.body].centerOfMass;
            results[i] = evaluateBuoyancyReference(bodies_[request.body].textures, frame, water,
                                                   request.fluid);
        }
        timings_.totalMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        return Ok{};
    }

    FrameTimings lastTimings() const override { return timings_; }

    std::size_t addExchangeSet(std::span<const ExchangeSample> samples,
                               std::size_t nodes) override {
        exchangeSets_.push_back({{samples.begin(), samples.end()}, nodes});
        return exchangeSets_.size() - 1;
    }

    Status evaluateExchange(std::size_t set, const ExchangeFrame& frame, const WaterModel& water,
                            ExchangeSums& sums) override {
        if (set >= exchangeSets_.size())
            return makeError(ErrorKind::invalidArgument, "evaluateExchange: unknown set id");
        evaluateExchangeReference(exchangeSets_[set].samples, exchangeSets_[set].nodes, frame,
                                  water, sums);
        return Ok{};
    }

private:
    struct Body {
        SurfaceTextures textures;
        Eigen::Vector3d centerOfMass;
    };
    struct ExchangeSet {
        std::vector<ExchangeSample> samples;
        std::size_t nodes = 0;
    };
    std::vector<Body> bodies_;
    std::vector<ExchangeSet> exchangeSets_;
    FrameTimings timings_;
};

std::string lower(std::string s) {
    for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return s;
}

}  // namespace

std::unique_ptr<BuoyancyBackend> createReferenceBackend() {
    return std::make_unique<ReferenceBackend>();
}

Result<std::unique_ptr<BuoyancyBackend>> createBuoyancyBackend(const std::string& requested,
                                                               std::string* notice,
                                                               const OpenClOptions& openCl) {
    std::string spec = lower(requested);
    if (spec.empty()) {
        if (const char* env = std::getenv("PLIMSOLL_OPENCL_DEVICE")) spec = lower(env);
    }
    if (spec == "reference" || spec == "none") {
        return std::unique_ptr<BuoyancyBackend>(createReferenceBackend());
    }
    if (spec == "fast") return createFastBackend();
    if (!openClAvailable()) {
        // Nothing to choose from: the automatic choice is the fast CPU path; a device asked
        // for by name cannot be had in this build.
        if (!spec.empty()) {
            return makeError(ErrorKind::unsupported,
                             "OpenCL device '" + requested +
                                 "': this build has no OpenCL (configured with "
                                 "PLIMSOLL_WITH_OPENCL=OFF); use --device fast or reference");
        }
        if (notice) *notice = "this build has no OpenCL: using the fast CPU path";
        return createFastBackend();
    }
    const std::vector<ComputeDevice> devices = listComputeDevices();
    if (devices.empty()) {
        if (notice) {
            *notice = "no OpenCL platform found: using the fast CPU path";
        }
        return createFastBackend();
    }
    auto describe = [&] {
        std::string list;
        for (const auto& d : devices)
            list += "\n  " + std::to_string(d.index) + ": " + d.name + " (" + d.platform +
                    (d.isGpu ? ", GPU" : ", CPU") + ")";
        return list;
    };
    int index = -1;
    if (spec.empty()) {
        for (const auto& d : devices) {
            if (d.isGpu) {
                index = d.index;
                break;
            }
        }
        // No GPU: the fast CPU path beats an OpenCL CPU device (ask for one with "cpu").
        if (index < 0) return createFastBackend();
    } else if (spec == "cpu" || spec == "gpu") {
        for (const auto& d : devices) {
            if (d.isGpu == (spec == "gpu")) {
                index = d.index;
                break;
            }
        }
        if (index < 0)
            return makeError(ErrorKind::device,
                             "no OpenCL " + spec + " device; devices:" + describe());
    } else {
        char* end = nullptr;
        const long n = std::strtol(spec.c_str(), &end, 10);
        if (end == spec.c_str() || *end != '\0' || n < 0 ||
            n >= static_cast<long>(devices.size())) {
            return makeError(ErrorKind::invalidArgument,
                             "unknown OpenCL device '" + requested +
                                 "' (cpu, gpu, reference, or an index); devices:" + describe());
        }
        index = static_cast<int>(n);
    }
    Result<std::unique_ptr<BuoyancyBackend>> opencl = detail::createOpenClBackend(index, openCl);
    // A device the user asked for by name must work; one chosen automatically may fail (a
    // driver that cannot build the kernels, a device out of resources): the fast CPU path
    // gives the same results within its stated error, and the notice says why.
    if (!opencl && spec.empty()) {
        if (notice) *notice = opencl.error().message + "\nusing the fast CPU path";
        return createFastBackend();
    }
    return opencl;
}

}  // namespace plimsoll
