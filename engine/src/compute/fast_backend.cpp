// The fast CPU backend over the shared evaluation core.
#include "plimsoll/compute/fast_backend.h"

#include "plimsoll/bake/bake.h"

#include <chrono>
#include <cstring>
#include <memory>
#include <thread>

namespace plimsoll {

namespace ev = plimsoll_eval;

namespace {

ev::Vec3 toEval(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d toEigen(const ev::Vec3& v) { return {v.x, v.y, v.z}; }

void waterHeights(const void* context, std::size_t n, const double* x, const double* z, double time,
                  double* out) {
    static_cast<const WaterModel*>(context)->heights(n, x, z, time, out);
}

void waterVelocities(const void* context, std::size_t n, const double* x, const double* y,
                     const double* z, double time, double* out) {
    static_cast<const WaterModel*>(context)->velocities(n, x, y, z, time, out);
}

class FastBackend final : public BuoyancyBackend {
public:
    explicit FastBackend(const FastBackendOptions& options)
        : options_(options),
          pool_(options.tasks.given()
                    ? 1
                    : (options.threads > 0
                           ? options.threads
                           : static_cast<int>(std::max(1u, std::thread::hardware_concurrency())))) {
        const int workers =
            options.tasks.given() ? std::max(1, options.tasks.workerCount) : pool_.threads();
        scratch_.resize(static_cast<std::size_t>(workers));
    }

    BackendKind kind() const override { return BackendKind::fastCpu; }

    std::string deviceName() const override {
        return "fast CPU (" + std::to_string(scratch_.size()) + " thread" +
               (scratch_.size() == 1 ? ")" : "s)");
    }

    std::size_t addBody(const SurfaceTextures& textures,
                        const Eigen::Vector3d& centerOfMass) override {
        bodies_.push_back(sharedBody(textures, centerOfMass));
        centers_.push_back(centerOfMass);
        return bodies_.size() - 1;
    }

    Status updateBody(std::size_t id, const SurfaceTextures& textures,
                      const Eigen::Vector3d& centerOfMass) override {
        if (id >= bodies_.size())
            return makeError(ErrorKind::invalidArgument, "updateBody: unknown body id");
        bodies_[id] = sharedBody(textures, centerOfMass);
        centers_[id] = centerOfMass;
        return Ok{};
    }

    Status evaluate(std::span<const BodyRequest> requests, const WaterModel& water,
                    std::span<BuoyancyResult> results) override {
        const auto start = std::chrono::steady_clock::now();
        for (const BodyRequest& request : requests)
            if (request.body >= bodies_.size())
                return makeError(ErrorKind::invalidArgument, "evaluate: unknown body id");
        auto one = [&](int i, std::uint32_t worker) {
            const BodyRequest& request = requests[static_cast<std::size_t>(i)];
            BodyFrame frame = request.frame;
            frame.centerOfMass = centers_[request.body];
            results[static_cast<std::size_t>(i)] =
                evaluateBuoyancyFast(*bodies_[request.body], frame, water, request.fluid,
                                     scratch_[worker % scratch_.size()]);
        };
        ev::parallelFor(static_cast<int>(requests.size()), 4, options_.tasks, pool_, one);
        timings_.totalMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        return Ok{};
    }

    FrameTimings lastTimings() const override { return timings_; }

    void forEach(std::size_t count, const std::function<void(std::size_t)>& work) override {
        auto one = [&](int i, std::uint32_t) { work(static_cast<std::size_t>(i)); };
        ev::parallelFor(static_cast<int>(count), 16, options_.tasks, pool_, one);
    }

    // The exchange pass of water graphs is the reference's (its samples are few).
    std::size_t addExchangeSet(std::span<const ExchangeSample> samples,
                               std::size_t nodes) override {
        return exchange_->addExchangeSet(samples, nodes);
    }

    Status evaluateExchange(std::size_t set, const ExchangeFrame& frame, const WaterModel& water,
                            ExchangeSums& sums) override {
        return exchange_->evaluateExchange(set, frame, water, sums);
    }

private:
    /// Bodies baked from the same textures about the same centre (a thousand crates of one
    /// asset) share one FastBody: its entries and nodes are then read from cache by every
    /// instance, where a copy each made a frame of many bodies a stream from memory (1000
    /// spheres at 64^2: 0.7 GB, 30-40 us a body on one thread or two, against 8 us alone).
    /// Found by a 64-bit hash of the entries' bytes and the centre (shared only on an equal
    /// hash and count).
    std::shared_ptr<const ev::FastBody> sharedBody(const SurfaceTextures& textures,
                                                   const Eigen::Vector3d& centerOfMass) {
        std::uint64_t key = 0x9e3779b97f4a7c15ull ^ textures.coveredCount();
        auto mix = [&key](const void* data, std::size_t bytes) {
            const auto* p = static_cast<const unsigned char*>(data);
            for (std::size_t i = 0; i + 8 <= bytes; i += 8) {
                std::uint64_t word;
                std::memcpy(&word, p + i, 8);
                key = (key ^ word) * 0xff51afd7ed558ccdull;
                key ^= key >> 32;
            }
        };
        mix(textures.position.data(), textures.position.size() * sizeof(Eigen::Vector3d));
        mix(textures.areaVector.data(), textures.areaVector.size() * sizeof(Eigen::Vector3d));
        mix(textures.area.data(), textures.area.size() * sizeof(double));
        mix(centerOfMass.data(), sizeof(double) * 3);
        for (const SharedBody& shared : shared_)
            if (shared.key == key && shared.count == textures.coveredCount()) return shared.body;
        auto body = std::make_shared<const ev::FastBody>(
            makeFastBody(textures, centerOfMass, options_.evaluation));
        shared_.push_back({key, textures.coveredCount(), body});
        return body;
    }

    struct SharedBody {
        std::uint64_t key;
        std::size_t count;
        std::shared_ptr<const ev::FastBody> body;
    };

    FastBackendOptions options_;
    ev::ThreadPool pool_;
    std::vector<SharedBody> shared_;
    std::vector<std::shared_ptr<const ev::FastBody>> bodies_;
    std::vector<Eigen::Vector3d> centers_;
    std::vector<ev::FastScratch> scratch_;  // one per worker
    std::unique_ptr<BuoyancyBackend> exchange_ = createReferenceBackend();
    FrameTimings timings_;
};

}  // namespace

ev::FastBody makeFastBody(const SurfaceTextures& textures, const Eigen::Vector3d& centerOfMass,
                          const ev::FastOptions& options) {
    ev::FastBody body;
    body.build(
        textures.coveredCount(),
        [&](std::size_t i, ev::Vec3& p, ev::Vec3& a, double& area) {
            p = toEval(textures.position[i]);
            a = toEval(textures.areaVector[i]);
            area = textures.area[i];
        },
        toEval(centerOfMass), options);
    return body;
}

ev::WaterSurface fastWaterSurface(const WaterModel& water) {
    ev::WaterSurface surface = ev::WaterSurface::flat(water.level);
    if (water.kind == WaterModel::Kind::Flat) return surface;
    surface.context = &water;
    surface.heights = waterHeights;
    surface.minHeight = water.minHeight();
    surface.maxHeight = water.maxHeight();
    // Only Gerstner water moves (water.h); the grid is still.
    if (water.kind == WaterModel::Kind::Gerstner) surface.velocities = waterVelocities;
    return surface;
}

BuoyancyResult evaluateBuoyancyFast(const ev::FastBody& body, const BodyFrame& frame,
                                    const WaterModel& water, const FluidSettings& fluid,
                                    ev::FastScratch& scratch, ev::FastStats* stats) {
    ev::BodyState state;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) state.rotation.m[i][j] = frame.pose.rotation(i, j);
    state.center = state.rotation * toEval(frame.centerOfMass) + toEval(frame.pose.translation);
    state.linear = toEval(frame.motion.linear);
    state.angular = toEval(frame.motion.angular);
    state.time = frame.time;
    ev::Coefficients k;
    k.rhoG = fluid.density * fluid.gravity;
    k.halfRhoCd = 0.5 * fluid.density * fluid.dragCoefficient;
    k.halfRhoCf = 0.5 * fluid.density * fluid.frictionCoefficient;
    const ev::Forces f = ev::finish(
        body.evaluate(state, fastWaterSurface(water), k, scratch, stats), state.center, k.rhoG);
    BuoyancyResult r;
    r.submergedVolume = f.submergedVolume;
    r.centerOfBuoyancy = toEigen(f.centerOfBuoyancy);
    r.force = toEigen(f.force);
    r.torque = toEigen(f.torque);
    r.pressureForce = toEigen(f.pressureForce);
    r.pressureTorque = toEigen(f.pressureTorque);
    r.dragForce = toEigen(f.dragForce);
    r.dragTorque = toEigen(f.dragTorque);
    r.wettedArea = f.wettedArea;
    r.submergedSamples = f.submergedSamples;
    return r;
}

std::unique_ptr<BuoyancyBackend> createFastBackend(const FastBackendOptions& options) {
    return std::make_unique<FastBackend>(options);
}

}  // namespace plimsoll
