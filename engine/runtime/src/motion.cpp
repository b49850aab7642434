// The load the water puts on a body each step, and a semi-implicit Euler step for a body on
// its own (docs/bundle.md "Runtime library"): what a physics-engine adapter applies and what
// it is tested against.
#include "plimsoll_runtime/runtime.hpp"

#include "bytes.hpp"
#include "motion.hpp"
#include "vec.hpp"

#include "plimsoll_eval/cummins.hpp"
#include "plimsoll_eval/sleep.hpp"

#include <algorithm>

namespace plimsoll_runtime {

namespace {

/// World inertia R I R^T times v.
Vec3 worldInertiaTimes(const double R[3][3], const double I[3][3], const Vec3& v) {
    const Vec3 b = mulT(R, v);
    return mul(R, Vec3{I[0][0] * b.x + I[0][1] * b.y + I[0][2] * b.z,
                       I[1][0] * b.x + I[1][1] * b.y + I[1][2] * b.z,
                       I[2][0] * b.x + I[2][1] * b.y + I[2][2] * b.z});
}

/// (R I R^T)^-1 v for a symmetric positive definite I (by cofactors; zero when singular).
Vec3 worldInertiaSolve(const double R[3][3], const double I[3][3], const Vec3& v) {
    const double c00 = I[1][1] * I[2][2] - I[1][2] * I[2][1];
    const double c01 = I[1][2] * I[2][0] - I[1][0] * I[2][2];
    const double c02 = I[1][0] * I[2][1] - I[1][1] * I[2][0];
    const double det = I[0][0] * c00 + I[0][1] * c01 + I[0][2] * c02;
    if (!(std::abs(det) > 0)) return {};
    const double inv[3][3] = {{c00 / det, (I[0][2] * I[2][1] - I[0][1] * I[2][2]) / det,
                               (I[0][1] * I[1][2] - I[0][2] * I[1][1]) / det},
                              {c01 / det, (I[0][0] * I[2][2] - I[0][2] * I[2][0]) / det,
                               (I[0][2] * I[1][0] - I[0][0] * I[1][2]) / det},
                              {c02 / det, (I[0][1] * I[2][0] - I[0][0] * I[2][1]) / det,
                               (I[0][0] * I[1][1] - I[0][1] * I[1][0]) / det}};
    return worldInertiaTimes(R, inv, v);
}

/// At most what stops `momentum` within dt (dissipation must not reverse the motion).
Vec3 limited(const Vec3& loss, const Vec3& momentum, double dt) {
    const double impulse = norm(loss) * dt, cap = norm(momentum);
    return impulse > cap && impulse > 0 ? (cap / impulse) * loss : loss;
}

/// Semi-implicit Euler's second half: the orientation turns with `w` and the centre of mass at
/// `center` moves with `v` for dt; R becomes the new orientation's matrix.
void moveWith(Pose& pose, const Vec3& center, const Vec3& v, const Vec3& w,
              const Vec3& centerOfMass, double dt, double R[3][3]) {
    Quat& q = pose.orientation;
    const Quat dq{-w.x * q.x - w.y * q.y - w.z * q.z, w.x * q.w + w.y * q.z - w.z * q.y,
                  w.y * q.w + w.z * q.x - w.x * q.z, w.z * q.w + w.x * q.y - w.y * q.x};
    q = {q.w + 0.5 * dt * dq.w, q.x + 0.5 * dt * dq.x, q.y + 0.5 * dt * dq.y,
         q.z + 0.5 * dt * dq.z};
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    q = {q.w / n, q.x / n, q.y / n, q.z / n};
    rotationMatrix(q, R);
    pose.position = center + dt * v - mul(R, centerOfMass);
}

}  // namespace

WaterLoad waterLoad(const Body& instance, const Pose& pose, const Velocity& velocity,
                    const Water& water, const Fluid& fluid, double time, double dt) {
    const Bundle& bundle = instance.bundle();
    WaterLoad load;
    load.forces = bundle.evaluate(pose, velocity, water, fluid, time);
    const Forces& f = load.forces;
    // On flat water Archimedes' form (exactly vertical: the texel sum's horizontal residue would
    // make a floating body creep); on waves the pressure integral, which carries their
    // horizontal push: what the editor's World applies (World::wrenchOf).
    const bool wavy = water.height || water.heights;
    load.force = wavy ? f.pressureForce : f.force;
    load.torque = wavy ? f.pressureTorque : f.torque;
    double R[3][3];
    rotationMatrix(pose.orientation, R);
    const MassProperties& body = bundle.mass();
    // The momenta the damping acts on are those of the body with its water (the water inside
    // moves with it), as in the World.
    double mass = body.mass, inertia[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) inertia[i][j] = body.inertia[i][j];
    if (const WaterGraph* graph = instance.graph()) {
        const MassProperties inside = graph->waterMass(pose.orientation);
        if (inside.mass > 0) {
            const Vec3 weight{0, -inside.mass * fluid.gravity, 0};
            load.force += weight;
            const Vec3 d = inside.centerOfMass - body.centerOfMass;
            load.torque += cross(mul(R, d), weight);
            load.waterMass = inside.mass;
            // The water's inertia about the body's centre of mass (parallel axes).
            const double dd = dot(d, d), dv[3] = {d.x, d.y, d.z};
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    inertia[i][j] +=
                        inside.inertia[i][j] + inside.mass * ((i == j ? dd : 0.0) - dv[i] * dv[j]);
            mass += inside.mass;
        }
    }
    const double wet =
        body.volume > 0 ? std::clamp(f.submergedVolume / body.volume, 0.0, 1.0) : 0.0;
    const Vec3 P = mass * velocity.linear;
    const Vec3 L = worldInertiaTimes(R, inertia, velocity.angular);
    Vec3 loss = f.dragForce - (wet * bundle.linearDamping()) * P;
    // Along gravity (-y) its own rate (radiation damps a radiating body's heave).
    if (bundle.verticalDamping() != bundle.linearDamping())
        loss.y -= wet * (bundle.verticalDamping() - bundle.linearDamping()) * P.y;
    load.force += limited(loss, P, dt);
    load.torque += limited(f.dragTorque - (wet * bundle.angularDamping()) * L, L, dt);
    return load;
}

namespace {

/// A step without radiation.
bool stepRigid(Body& instance, BodyState& state, const Water& water, const Fluid& fluid,
               double time, double dt) {
    WaterGraph* graph = instance.graph();
    const bool moved = graph && graph->step(state.pose, water, time, dt);
    const WaterLoad load = waterLoad(instance, state.pose, state.velocity, water, fluid, time, dt);
    const MassProperties& body = instance.bundle().mass();
    double R[3][3];
    rotationMatrix(state.pose.orientation, R);
    const Vec3 center = mul(R, body.centerOfMass) + state.pose.position;
    // Momenta first ...
    const Vec3 P = body.mass * state.velocity.linear +
                   dt * (load.force + Vec3{0, -body.mass * fluid.gravity, 0});
    const Vec3 L = worldInertiaTimes(R, body.inertia, state.velocity.angular) + dt * load.torque;
    const Vec3 v = (1.0 / body.mass) * P;
    const Vec3 w = worldInertiaSolve(R, body.inertia, L);
    // ... then position and orientation with the new velocities.
    moveWith(state.pose, center, v, w, body.centerOfMass, dt, R);
    state.velocity.linear = v;
    // The angular velocity that carries L at the new orientation: L is what is conserved.
    state.velocity.angular = worldInertiaSolve(R, body.inertia, L);
    return moved;
}

}  // namespace

RadiationMemory::RadiationMemory(const Radiation* radiation) : radiation_(radiation) {
    if (!radiation_) return;
    for (int mode = 0; mode < 6; ++mode)
        filters_[mode].assign(radiation_->memory[mode].size(), Filter{});
}

namespace {
plimsoll_eval::MemoryTerm coreTerm(const RadiationTerm& t) {
    return {t.gain, t.frequency, t.dampingRatio};
}
}  // namespace

RadiationLoad RadiationMemory::begin(const Pose& pose, double submergedVolume) {
    RadiationLoad load;
    load.previousShare = started_ ? share_ : -1.0;
    started_ = true;
    if (!radiation_) {
        share_ = 0;
        return load;
    }
    share_ = plimsoll_eval::entrainedShare(submergedVolume, radiation_->restVolume);
    load.share = share_;
    radiation_->sharedAddedMass(share_, load.addedMass, load.addedInertia);
    // The memory's generalised force (body axes), scaled by the share like its input.
    double f[6] = {0, 0, 0, 0, 0, 0};
    for (int mode = 0; mode < 6; ++mode) {
        for (std::size_t k = 0; k < filters_[mode].size(); ++k) {
            const plimsoll_eval::MemoryFilter filter{filters_[mode][k].x, filters_[mode][k].rate};
            f[mode] += plimsoll_eval::filterForce(coreTerm(radiation_->memory[mode][k]), filter);
        }
    }
    double R[3][3];
    rotationMatrix(pose.orientation, R);
    load.force = mul(R, Vec3{share_ * f[0], share_ * f[1], share_ * f[2]});
    load.torque = mul(R, Vec3{share_ * f[3], share_ * f[4], share_ * f[5]});
    return load;
}

void RadiationMemory::advance(const Pose& pose, const Velocity& velocity, double dt) {
    if (!radiation_) return;
    double R[3][3];
    rotationMatrix(pose.orientation, R);
    const Vec3 linear = mulT(R, velocity.linear), angular = mulT(R, velocity.angular);
    const double v[6] = {linear.x, linear.y, linear.z, angular.x, angular.y, angular.z};
    for (int mode = 0; mode < 6; ++mode) {
        for (std::size_t k = 0; k < filters_[mode].size(); ++k) {
            plimsoll_eval::MemoryFilter filter{filters_[mode][k].x, filters_[mode][k].rate};
            plimsoll_eval::advanceFilter(coreTerm(radiation_->memory[mode][k]), filter,
                                         share_ * v[mode], dt);
            filters_[mode][k] = {filter.x, filter.rate};
        }
    }
}

double RadiationMemory::energy() const {
    if (!radiation_) return 0;
    double e = 0;
    for (int mode = 0; mode < 6; ++mode) {
        for (std::size_t k = 0; k < filters_[mode].size(); ++k) {
            const plimsoll_eval::MemoryFilter filter{filters_[mode][k].x, filters_[mode][k].rate};
            e += plimsoll_eval::filterEnergy(coreTerm(radiation_->memory[mode][k]), filter);
        }
    }
    return e;
}

namespace {

/// A step with the added mass and the memory of `memory`.
bool stepRadiating(Body& instance, BodyState& state, RadiationMemory& memory, const Water& water,
                   const Fluid& fluid, double time, double dt) {
    const Bundle& bundle = instance.bundle();
    WaterGraph* graph = instance.graph();
    const bool moved = graph && graph->step(state.pose, water, time, dt);
    const WaterLoad load = waterLoad(instance, state.pose, state.velocity, water, fluid, time, dt);
    const RadiationLoad radiation = memory.begin(state.pose, load.forces.submergedVolume);
    const MassProperties& body = bundle.mass();
    // The mass matrices with an added mass, body axes (translations, rotations).
    auto withAdded = [&](const double added[3][3], const double addedInertia[3][3],
                         double translational[3][3], double rotational[3][3]) {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                translational[i][j] = (i == j ? body.mass : 0.0) + added[i][j];
                rotational[i][j] = body.inertia[i][j] + addedInertia[i][j];
            }
        }
    };
    double M[3][3], I[3][3];
    withAdded(radiation.addedMass, radiation.addedInertia, M, I);  // begin() formed this share's
    double R[3][3];
    rotationMatrix(state.pose.orientation, R);
    Vec3 v = state.velocity.linear, w = state.velocity.angular;
    if (radiation.previousShare >= 0 && radiation.share > radiation.previousShare) {
        // More water entrained: the momentum is kept (the velocity falls).
        double added[3][3] = {}, addedInertia[3][3] = {}, Mp[3][3], Ip[3][3];
        if (const Radiation* r = bundle.radiation())
            r->sharedAddedMass(radiation.previousShare, added, addedInertia);
        withAdded(added, addedInertia, Mp, Ip);
        v = worldInertiaSolve(R, M, worldInertiaTimes(R, Mp, v));
        w = worldInertiaSolve(R, I, worldInertiaTimes(R, Ip, w));
    }
    const Vec3 center = mul(R, body.centerOfMass) + state.pose.position;
    const Vec3 P = worldInertiaTimes(R, M, v) +
                   dt * (load.force + radiation.force + Vec3{0, -body.mass * fluid.gravity, 0});
    const Vec3 L = worldInertiaTimes(R, I, w) + dt * (load.torque + radiation.torque);
    const Vec3 vNext = worldInertiaSolve(R, M, P);
    moveWith(state.pose, center, vNext, worldInertiaSolve(R, I, L), body.centerOfMass, dt, R);
    state.velocity.linear = vNext;
    state.velocity.angular = worldInertiaSolve(R, I, L);
    memory.advance(state.pose, state.velocity, dt);
    return moved;
}

}  // namespace

bool stepBodyWith(Body& body, BodyState& state, RadiationMemory* memory, const Water& water,
                  const Fluid& fluid, double time, double dt) {
    return memory ? stepRadiating(body, state, *memory, water, fluid, time, dt)
                  : stepRigid(body, state, water, fluid, time, dt);
}

namespace {

bool samePose(const Pose& a, const Pose& b) {
    return a.position.x == b.position.x && a.position.y == b.position.y &&
           a.position.z == b.position.z && a.orientation.w == b.orientation.w &&
           a.orientation.x == b.orientation.x && a.orientation.y == b.orientation.y &&
           a.orientation.z == b.orientation.z;
}

}  // namespace

plimsoll_eval::SleepSettings sleepSettingsOf(const BundleWorld::Sleep& s) {
    plimsoll_eval::SleepSettings out;
    out.enabled = s.enabled;
    out.linearSpeed = s.linearSpeed;
    out.angularSpeed = s.angularSpeed;
    out.linearAcceleration = s.linearAcceleration;
    out.angularAcceleration = s.angularAcceleration;
    out.restTime = s.restTime;
    out.wakeHeight = s.wakeHeight;
    return out;
}

void surfaceAbove(const Water& water, const Vec3& point, double time, double& height,
                  double& speed) {
    height = water.heightAt(point.x, point.z, time);
    const Vec3 at{point.x, height, point.z};
    Vec3 u{0, 0, 0};
    if (water.velocities) {
        double out[3] = {0, 0, 0};
        water.velocities(1, &at.x, &at.y, &at.z, time, out);
        u = {out[0], out[1], out[2]};
    } else if (water.velocity) {
        u = water.velocity(at, time);
    }
    speed = norm(u);
}

void stepBody(Body& body, BodyState& state, const Water& water, const Fluid& fluid, double time,
              double dt) {
    const plimsoll_eval::SleepSettings settings = sleepSettingsOf(body.bundle().world().sleep);
    Body::Sleep& sleep = body.sleep_;
    const MassProperties& mass = body.bundle().mass();
    auto centerOf = [&](const Pose& pose) {
        double R[3][3];
        rotationMatrix(pose.orientation, R);
        return mul(R, mass.centerOfMass) + pose.position;
    };
    if (sleep.asleep) {
        // The game moved it or set it going: awake. Otherwise the water decides.
        const Velocity& v = state.velocity;
        const bool moved =
            !samePose(state.pose, sleep.pose) || norm(v.linear) > 0 || norm(v.angular) > 0;
        double height = 0, speed = 0;
        surfaceAbove(water, centerOf(state.pose), time, height, speed);
        plimsoll_eval::SleepState rest{true, sleep.restedFor, sleep.waterHeight};
        if (!moved && !plimsoll_eval::mustWake(rest, settings, speed, height, false)) return;
        body.wake();
    }
    const Velocity before = state.velocity;
    const bool changing = stepBodyWith(body, state, body.radiation(), water, fluid, time, dt);
    plimsoll_eval::RestSample sample;
    sample.speed = norm(state.velocity.linear);
    sample.spin = norm(state.velocity.angular);
    sample.acceleration = norm(state.velocity.linear - before.linear) / dt;
    sample.angularAcceleration = norm(state.velocity.angular - before.angular) / dt;
    plimsoll_eval::sampleWaterIfStill(settings, sample, [&](double& height, double& speed) {
        surfaceAbove(water, centerOf(state.pose), time + dt, height, speed);
    });
    sample.changing = changing;
    plimsoll_eval::SleepState rest{false, sleep.restedFor, sleep.waterHeight};
    if (plimsoll_eval::countRest(rest, settings, sample, dt)) {
        state.velocity = Velocity{};
        sleep.pose = state.pose;
    }
    sleep.asleep = rest.asleep;
    sleep.restedFor = rest.restedFor;
    sleep.waterHeight = rest.waterHeight;
}

void RadiationMemory::saveState(std::vector<std::uint8_t>& out) const {
    for (const std::vector<Filter>& mode : filters_) {
        putBytes(out, static_cast<std::uint64_t>(mode.size()));
        for (const Filter& f : mode) {
            putBytes(out, f.x);
            putBytes(out, f.rate);
        }
    }
    putBytes(out, share_);
    putBytes(out, static_cast<std::uint8_t>(started_ ? 1 : 0));
}

bool RadiationMemory::restoreState(const std::vector<std::uint8_t>& in, std::size_t& at) {
    std::size_t cursor = at;
    std::vector<Filter> filters[6];
    for (int mode = 0; mode < 6; ++mode) {
        std::uint64_t count = 0;
        if (!takeBytes(in, cursor, count) || count != filters_[mode].size()) return false;
        filters[mode].resize(count);
        for (Filter& f : filters[mode]) {
            if (!takeBytes(in, cursor, f.x) || !takeBytes(in, cursor, f.rate) ||
                !std::isfinite(f.x) || !std::isfinite(f.rate))
                return false;
        }
    }
    double share = 0;
    std::uint8_t started = 0;
    if (!takeBytes(in, cursor, share) || !takeBytes(in, cursor, started) ||
        !(share >= 0 && share <= 1) || started > 1)
        return false;
    for (int mode = 0; mode < 6; ++mode) filters_[mode] = std::move(filters[mode]);
    share_ = share;
    started_ = started == 1;
    at = cursor;
    return true;
}

}  // namespace plimsoll_runtime
