// Buoyancy, pressure and drag over the bundle's sample list: the engine's fast CPU path,
// compiled from the shared evaluation core (plimsoll_eval/fast.hpp), so that a bundle floats
// here exactly as in the engine (tests/runtime/test_runtime_conformance.cpp holds the two
// equal).
#include "plimsoll_runtime/runtime.hpp"

#include "vec.hpp"

#include "plimsoll_eval/entry.hpp"
#include "plimsoll_eval/fast.hpp"

namespace plimsoll_runtime {

namespace ev = plimsoll_eval;

namespace {

void callerHeights(const void* context, std::size_t n, const double* x, const double* z,
                   double time, double* out) {
    const Water& water = *static_cast<const Water*>(context);
    if (water.heights) return water.heights(n, x, z, time, out);
    for (std::size_t i = 0; i < n; ++i) out[i] = water.height(x[i], z[i], time);
}

void callerVelocities(const void* context, std::size_t n, const double* x, const double* y,
                      const double* z, double time, double* out) {
    const Water& water = *static_cast<const Water*>(context);
    if (water.velocities) return water.velocities(n, x, y, z, time, out);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 v = water.velocity(Vec3{x[i], y[i], z[i]}, time);
        out[3 * i] = v.x;
        out[3 * i + 1] = v.y;
        out[3 * i + 2] = v.z;
    }
}

/// A FastBody over `samples`, its entries relative to `center`.
std::shared_ptr<const ev::FastBody> buildFast(const std::vector<Sample>& samples,
                                              const Vec3& center) {
    auto body = std::make_shared<ev::FastBody>();
    body->build(
        samples.size(),
        [&samples](std::size_t i, ev::Vec3& p, ev::Vec3& a, double& area) {
            p = toEval(samples[i].position);
            a = toEval(samples[i].areaVector);
            area = samples[i].area;
        },
        toEval(center));
    return body;
}

/// The fast path over `fast` (entries about the body's centre of mass `center`).
Forces evaluateOver(const ev::FastBody& fast, const Vec3& center, const Pose& pose,
                    const Velocity& velocity, const Water& water, const Fluid& fluid, double time) {
    ev::BodyState state;
    state.rotation = ev::rotationMatrix(
        {pose.orientation.w, pose.orientation.x, pose.orientation.y, pose.orientation.z});
    state.center = state.rotation * toEval(center) + toEval(pose.position);
    state.linear = toEval(velocity.linear);
    state.angular = toEval(velocity.angular);
    state.time = time;
    ev::WaterSurface surface = ev::WaterSurface::flat(water.level);
    if (water.height || water.heights) {
        surface.context = &water;
        surface.heights = callerHeights;
        surface.minHeight = water.minHeight;
        surface.maxHeight = water.maxHeight;
    }
    if (water.velocity || water.velocities) {
        surface.context = &water;
        surface.velocities = callerVelocities;
    }
    ev::Coefficients k;
    k.rhoG = fluid.density * fluid.gravity;
    k.halfRhoCd = 0.5 * fluid.density * fluid.dragCoefficient;
    k.halfRhoCf = 0.5 * fluid.density * fluid.frictionCoefficient;
    // Per thread: sized on a thread's first call, reused after.
    thread_local ev::FastScratch scratch;
    const ev::Forces f =
        ev::finish(fast.evaluate(state, surface, k, scratch), state.center, k.rhoG);
    Forces out;
    out.submergedVolume = f.submergedVolume;
    out.centerOfBuoyancy = fromEval(f.centerOfBuoyancy);
    out.force = fromEval(f.force);
    out.torque = fromEval(f.torque);
    out.pressureForce = fromEval(f.pressureForce);
    out.pressureTorque = fromEval(f.pressureTorque);
    out.dragForce = fromEval(f.dragForce);
    out.dragTorque = fromEval(f.dragTorque);
    out.wettedArea = f.wettedArea;
    out.submergedSamples = f.submergedSamples;
    return out;
}

}  // namespace

void rotationMatrix(const Quat& q, double R[3][3]) {
    const ev::Mat3 m = ev::rotationMatrix({q.w, q.x, q.y, q.z});
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) R[i][j] = m.m[i][j];
}

const ev::FastBody& Bundle::fastBody() const {
    std::call_once(fastOnce_, [this] {
        fast_ = buildFast(samples_, mass_.centerOfMass);
        fastBuilt_.store(true, std::memory_order_release);
    });
    return *fast_;
}

std::uint64_t Bundle::fastBytes() const {
    std::uint64_t bytes = 0;
    if (fastBuilt_.load(std::memory_order_acquire))
        bytes += sizeof(ev::FastBody) + fast_->memoryBytes();
    for (const std::unique_ptr<CoarseLevel>& level : coarse_) {
        bytes += sizeof(CoarseLevel) + level->samples.capacity() * sizeof(Sample);
        if (level->built.load(std::memory_order_acquire))
            bytes += sizeof(ev::FastBody) + level->fast->memoryBytes();
    }
    return bytes;
}

Forces Bundle::evaluate(const Pose& pose, const Velocity& velocity, const Water& water,
                        const Fluid& fluid, double time) const {
    return evaluateOver(fastBody(), mass_.centerOfMass, pose, velocity, water, fluid, time);
}

Forces Bundle::evaluateLevel(std::size_t level, const Pose& pose, const Velocity& velocity,
                             const Water& water, const Fluid& fluid, double time) const {
    if (level >= coarse_.size()) return evaluate(pose, velocity, water, fluid, time);
    const CoarseLevel& c = *coarse_[level];
    std::call_once(c.once, [&c, this] {
        c.fast = buildFast(c.samples, mass_.centerOfMass);
        c.built.store(true, std::memory_order_release);
    });
    return evaluateOver(*c.fast, mass_.centerOfMass, pose, velocity, water, fluid, time);
}

}  // namespace plimsoll_runtime
