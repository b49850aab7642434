// The WebAssembly module's exports: a flat C interface over the runtime's C++ API
// (plimsoll_runtime/runtime.hpp) that web/package/index.js wraps. Poses, velocities and results
// travel as arrays of doubles in the module's memory, so JavaScript reads them with one
// Float64Array and no struct layouts. Water is one of three: the bundle's own (its world's flat
// or Gerstner model), flat at a level, or a JavaScript callback asked for many heights per call
// (the imports below, which index.js supplies).
#include "plimsoll_runtime/runtime.hpp"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#define PW_EXPORT extern "C" __attribute__((used, visibility("default")))
#define PW_IMPORT(name) __attribute__((import_module("env"), import_name(name)))

// JavaScript's water: out[i] = height at (x[i], z[i]) for the callback registered as `id`;
// velocities out[3 i..3 i + 2] at (x[i], y[i], z[i]) (when the callback has them).
extern "C" PW_IMPORT("pw_js_heights") void pw_js_heights(int id, std::size_t n, const double* x,
                                                         const double* z, double time, double* out);
extern "C" PW_IMPORT("pw_js_velocities") void pw_js_velocities(int id, std::size_t n,
                                                               const double* x, const double* y,
                                                               const double* z, double time,
                                                               double* out);

namespace {

namespace rt = plimsoll_runtime;

std::string lastError;

struct WebBundle {
    std::unique_ptr<rt::Bundle> bundle;
    rt::Water own;  // the bundle's world water (flat or its waves)
};

// Water modes of every call that takes water.
enum WaterMode { kOwn = 0, kFlat = 1, kCallback = 2 };

rt::Water waterFor(const WebBundle& b, int mode, double level, int id, int hasVelocities,
                   double minHeight, double maxHeight) {
    if (mode == kOwn) return b.own;
    rt::Water w;
    w.level = level;
    if (mode == kCallback) {
        w.heights = [id](std::size_t n, const double* x, const double* z, double t, double* out) {
            pw_js_heights(id, n, x, z, t, out);
        };
        if (hasVelocities)
            w.velocities = [id](std::size_t n, const double* x, const double* y, const double* z,
                                double t,
                                double* out) { pw_js_velocities(id, n, x, y, z, t, out); };
        w.minHeight = minHeight;
        w.maxHeight = maxHeight;
    }
    return w;
}

rt::Pose poseFrom(const double* p) {
    rt::Pose pose;
    pose.position = {p[0], p[1], p[2]};
    pose.orientation = {p[3], p[4], p[5], p[6]};
    return pose;
}

void put(double* to, const rt::Vec3& v) { to[0] = v.x, to[1] = v.y, to[2] = v.z; }

// Forces as 24 doubles: submerged volume, centre of buoyancy (3), force, torque, pressure force,
// pressure torque, drag force, drag torque (3 each), wetted area, submerged samples.
void putForces(double* out, const rt::Forces& f) {
    out[0] = f.submergedVolume;
    put(out + 1, f.centerOfBuoyancy);
    put(out + 4, f.force);
    put(out + 7, f.torque);
    put(out + 10, f.pressureForce);
    put(out + 13, f.pressureTorque);
    put(out + 16, f.dragForce);
    put(out + 19, f.dragTorque);
    out[22] = f.wettedArea;
    out[23] = static_cast<double>(f.submergedSamples);
}

// A fluid as 4 doubles: density, gravity, drag coefficient, friction coefficient.
rt::Fluid fluidFrom(const double* in) {
    rt::Fluid fluid;
    fluid.density = in[0], fluid.gravity = in[1], fluid.dragCoefficient = in[2],
    fluid.frictionCoefficient = in[3];
    return fluid;
}

bool finite(const double* v, int n) {
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

void putHash(std::uint64_t h, std::uint32_t* out) {
    out[0] = static_cast<std::uint32_t>(h >> 32);
    out[1] = static_cast<std::uint32_t>(h);
}

struct WebBody {
    const WebBundle* bundle;
    rt::Body body;
    explicit WebBody(const WebBundle& b) : bundle(&b), body(*b.bundle) {}
};

struct WebSimulation {
    const WebBundle* bundle;
    std::unique_ptr<rt::Simulation> simulation;
};

}  // namespace

PW_EXPORT void* pw_alloc(std::size_t bytes) { return std::malloc(bytes ? bytes : 1); }
PW_EXPORT void pw_free(void* p) { std::free(p); }
PW_EXPORT const char* pw_last_error() { return lastError.c_str(); }
PW_EXPORT const char* pw_version() {
    static const std::string v = [] {
        const rt::Version r = rt::runtimeVersion();
        return std::to_string(r.major) + "." + std::to_string(r.minor) + "." +
               std::to_string(r.patch);
    }();
    return v.c_str();
}

// count files: paths[i] (NUL-terminated), data[i], sizes[i]. Null with the error on failure.
PW_EXPORT WebBundle* pw_bundle_load(std::size_t count, const char* const* paths,
                                    const unsigned char* const* data, const std::uint32_t* sizes,
                                    const char* name, int verify) {
    lastError.clear();
    std::vector<rt::MemoryFile> files(count);
    for (std::size_t i = 0; i < count; ++i) files[i] = {paths[i], data[i], sizes[i]};
    rt::LoadOptions options;
    options.verifyChecksums = verify != 0;
    std::string error;
    auto bundle = rt::loadBundleFromMemory(files, name ? name : "memory", error, options);
    if (!bundle) {
        lastError = error;
        return nullptr;
    }
    auto* b = new WebBundle;
    b->own = bundle->world().water.water();
    b->bundle = std::move(bundle);
    return b;
}

PW_EXPORT void pw_bundle_destroy(WebBundle* b) { delete b; }
PW_EXPORT const char* pw_bundle_body(const WebBundle* b) { return b->bundle->body().c_str(); }

// 40 doubles: mass, volume, centre of mass (3), inertia (9, row major), samples, graph nodes,
// fluid density, gravity, drag coefficient, friction coefficient, linear, vertical and angular
// damping, frame time, sub-steps, water kind (0 flat, 1 Gerstner, 2 height grid), water level,
// wave count, start position (3), start orientation (4), bounds min (3), max (3), texture size.
PW_EXPORT void pw_bundle_info(const WebBundle* wb, double* out) {
    const rt::Bundle& b = *wb->bundle;
    const rt::MassProperties& m = b.mass();
    out[0] = m.mass;
    out[1] = m.volume;
    put(out + 2, m.centerOfMass);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out[5 + 3 * i + j] = m.inertia[i][j];
    out[14] = static_cast<double>(b.samples().size());
    out[15] = b.graph() ? static_cast<double>(b.graph()->nodes().size()) : 0.0;
    const rt::BundleWorld& w = b.world();
    // The bundle's fluid: its world's density and gravity, the manifest's coefficients.
    out[16] = b.fluid().density;
    out[17] = b.fluid().gravity;
    out[18] = b.fluid().dragCoefficient;
    out[19] = b.fluid().frictionCoefficient;
    out[20] = b.linearDamping();
    out[21] = b.verticalDamping();
    out[22] = b.angularDamping();
    out[23] = w.timeStep;
    out[24] = w.subSteps;
    out[25] = static_cast<double>(static_cast<int>(w.water.kind));
    out[26] = w.water.level;
    out[27] = static_cast<double>(w.water.waves.size());
    put(out + 28, w.startPose.position);
    out[31] = w.startPose.orientation.w, out[32] = w.startPose.orientation.x;
    out[33] = w.startPose.orientation.y, out[34] = w.startPose.orientation.z;
    rt::Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const rt::Sample& s : b.samples()) {
        lo = {std::min(lo.x, s.position.x), std::min(lo.y, s.position.y),
              std::min(lo.z, s.position.z)};
        hi = {std::max(hi.x, s.position.x), std::max(hi.y, s.position.y),
              std::max(hi.z, s.position.z)};
    }
    put(out + 35, lo);
    put(out + 38, hi);
    out[41] = b.textureSize();
}

// Wave i of the bundle's water: amplitude, wavelength, direction x, z, steepness, phase.
PW_EXPORT void pw_bundle_wave(const WebBundle* wb, int i, double* out) {
    const auto& w = wb->bundle->world().water.waves.at(static_cast<std::size_t>(i));
    out[0] = w.amplitude, out[1] = w.wavelength, out[2] = w.direction[0], out[3] = w.direction[1];
    out[4] = w.steepness, out[5] = w.phase;
}

PW_EXPORT double pw_bundle_node_capacity(const WebBundle* wb, int node) {
    return wb->bundle->graph()->nodes().at(static_cast<std::size_t>(node)).capacity;
}

// The bundle's own water's heights at n points (for drawing the surface the physics sees).
PW_EXPORT void pw_bundle_water_heights(const WebBundle* wb, std::size_t n, const double* x,
                                       const double* z, double time, double* out) {
    const rt::Water& w = wb->own;
    if (w.heights) {
        w.heights(n, x, z, time, out);
    } else {
        for (std::size_t i = 0; i < n; ++i) out[i] = w.level;
    }
}

// in: pose (7), velocity (6), time, fluid (4: density, gravity, drag, friction); out: 24 forces.
PW_EXPORT int pw_bundle_evaluate(const WebBundle* wb, const double* in, int waterMode, double level,
                                 int id, int hasVelocities, double minHeight, double maxHeight,
                                 double* out) {
    lastError.clear();
    if (!finite(in, 18)) {
        lastError = "evaluate: the pose, velocity, time or fluid has a NaN or Inf";
        return 0;
    }
    rt::Velocity v;
    v.linear = {in[7], in[8], in[9]};
    v.angular = {in[10], in[11], in[12]};
    const rt::Fluid fluid = fluidFrom(in + 14);
    const rt::Water water =
        waterFor(*wb, waterMode, level, id, hasVelocities, minHeight, maxHeight);
    const rt::Forces f = wb->bundle->evaluate(poseFrom(in), v, water, fluid, in[13]);
    putForces(out, f);
    if (!finite(out, 24)) {
        lastError = "evaluate: the result is not finite (did the water callback return NaN?)";
        return 0;
    }
    return 1;
}

PW_EXPORT WebBody* pw_body_create(const WebBundle* wb) { return new WebBody(*wb); }
PW_EXPORT void pw_body_destroy(WebBody* b) { delete b; }

// state: pose (7), linear velocity (3), angular velocity (3), in and out; fluid (4). With
// out null, one semi-implicit Euler step of dt (the runtime's stepBody); with out, no step: the
// water load at that state (waterLoad, what a step of dt applies) into out: its forces (24), the
// water mass, then the load's force (3) and torque (3).
PW_EXPORT int pw_body_step(WebBody* body, double* state, const double* fluidIn, double time,
                           double dt, int waterMode, double level, int id, int hasVelocities,
                           double minHeight, double maxHeight, double* out) {
    lastError.clear();
    if (!finite(state, 13) || !finite(fluidIn, 4) || !std::isfinite(time) || !(dt > 0)) {
        lastError = "step: the state, fluid, time or dt is not finite (or dt <= 0)";
        return 0;
    }
    const rt::Fluid fluid = fluidFrom(fluidIn);
    const rt::Water water =
        waterFor(*body->bundle, waterMode, level, id, hasVelocities, minHeight, maxHeight);
    rt::BodyState s;
    s.pose = poseFrom(state);
    s.velocity.linear = {state[7], state[8], state[9]};
    s.velocity.angular = {state[10], state[11], state[12]};
    if (out) {
        const rt::WaterLoad load =
            rt::waterLoad(body->body, s.pose, s.velocity, water, fluid, time, dt);
        putForces(out, load.forces);
        out[24] = load.waterMass;
        put(out + 25, load.force);
        put(out + 28, load.torque);
        if (!finite(out, 31)) {
            lastError = "load: the result is not finite (did the water callback return NaN?)";
            return 0;
        }
        return 1;
    }
    rt::stepBody(body->body, s, water, fluid, time, dt);
    const double next[13] = {s.pose.position.x,    s.pose.position.y,    s.pose.position.z,
                             s.pose.orientation.w, s.pose.orientation.x, s.pose.orientation.y,
                             s.pose.orientation.z, s.velocity.linear.x,  s.velocity.linear.y,
                             s.velocity.linear.z,  s.velocity.angular.x, s.velocity.angular.y,
                             s.velocity.angular.z};
    if (!finite(next, 13)) {
        lastError = "step: the state left the finite numbers (did the water callback return NaN?)";
        return 0;
    }
    std::memcpy(state, next, sizeof next);
    return 1;
}

PW_EXPORT int pw_body_node_water(const WebBody* b, double* out) {
    const rt::WaterGraph* g = b->body.graph();
    if (!g) return 0;
    const std::size_t n = b->bundle->bundle->graph()->nodes().size();
    for (std::size_t i = 0; i < n; ++i) out[i] = g->water(i);
    return static_cast<int>(n);
}
PW_EXPORT void pw_body_hash(const WebBody* b, std::uint32_t* out) {
    putHash(b->body.stateHash(), out);
}
PW_EXPORT int pw_body_asleep(const WebBody* b) { return b->body.asleep() ? 1 : 0; }
PW_EXPORT void pw_body_wake(WebBody* b) { b->body.wake(); }

PW_EXPORT WebSimulation* pw_simulation_create(const WebBundle* wb) {
    lastError.clear();
    std::string error;
    auto s = rt::Simulation::create(*wb->bundle, error);
    if (!s) {
        lastError = error;
        return nullptr;
    }
    return new WebSimulation{wb, std::move(s)};
}
PW_EXPORT void pw_simulation_destroy(WebSimulation* s) { delete s; }

PW_EXPORT int pw_simulation_advance(WebSimulation* s, int waterMode, double level, int id,
                                    int hasVelocities, double minHeight, double maxHeight) {
    lastError.clear();
    const rt::Water water =
        waterFor(*s->bundle, waterMode, level, id, hasVelocities, minHeight, maxHeight);
    std::string error;
    if (!s->simulation->advanceFrame(water, error)) {
        lastError = error;
        return 0;
    }
    return 1;
}

// The columns of `plimsoll simulate --out` and plimsoll_simulation_state (22 doubles): time,
// centre of mass (3), orientation w x y z, velocity (3), angular velocity (3), submerged volume,
// buoyant force (3), mass, local centre of mass (3); then the frame time and the sub-steps.
PW_EXPORT void pw_simulation_state(const WebSimulation* ws, double* out) {
    const rt::Simulation& s = *ws->simulation;
    out[0] = s.time();
    put(out + 1, s.centerOfMass());
    const rt::Quat& q = s.orientation();
    out[4] = q.w, out[5] = q.x, out[6] = q.y, out[7] = q.z;
    put(out + 8, s.linearVelocity());
    put(out + 11, s.angularVelocity());
    out[14] = s.forces().submergedVolume;
    put(out + 15, s.forces().pressureForce);
    out[18] = s.mass().mass;
    put(out + 19, s.mass().centerOfMass);
    out[22] = s.frameTime();
    out[23] = s.subSteps();
}

// One row of float_body --csv (its printf format, so the text is byte for byte the native one).
PW_EXPORT int pw_simulation_csv_row(const WebSimulation* ws, char* buffer, int capacity) {
    double v[24];
    pw_simulation_state(ws, v);
    return std::snprintf(
        buffer, static_cast<std::size_t>(capacity),
        "%.10g,%s,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,"
        "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n",
        v[0], ws->bundle->bundle->body().c_str(), v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8],
        v[9], v[10], v[11], v[12], v[13], v[14], v[15], v[16], v[17], v[18], v[19], v[20], v[21]);
}

PW_EXPORT void pw_simulation_hash(const WebSimulation* s, std::uint32_t* out) {
    putHash(s->simulation->stateHash(), out);
}
PW_EXPORT int pw_simulation_node_water(const WebSimulation* s, double* out) {
    const rt::WaterGraph* g = s->simulation->graph();
    if (!g) return 0;
    const std::size_t n = s->bundle->bundle->graph()->nodes().size();
    for (std::size_t i = 0; i < n; ++i) out[i] = g->water(i);
    return static_cast<int>(n);
}
PW_EXPORT int pw_simulation_asleep(const WebSimulation* s) {
    return s->simulation->asleep() ? 1 : 0;
}
