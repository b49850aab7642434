// The C API (plimsoll_runtime.h) over the C++ one: every entry point catches, so no exception
// crosses into C.
#include "plimsoll_runtime.h"

#include "plimsoll_runtime/runtime.hpp"

#include "motion.hpp"

#include "plimsoll_eval/tasks.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

struct plimsoll_instance {
    const plimsoll_bundle* bundle;
    plimsoll_runtime::Body body;
    /// The state before the step in progress, put back when the step is refused; kept between
    /// steps so that saving it allocates nothing.
    std::vector<std::uint8_t> undo = {};
};

struct plimsoll_bundle {
    std::unique_ptr<plimsoll_runtime::Bundle> bundle;
    /// The body the deprecated 1.x calls step: before 2.0 the bundle held its water itself.
    std::unique_ptr<plimsoll_instance> legacy;
};

struct plimsoll_radiation_memory {
    const plimsoll_runtime::Bundle* bundle;  ///< the bundle whose radiation it steps
    plimsoll_runtime::RadiationMemory memory;
};

struct plimsoll_simulation {
    std::unique_ptr<plimsoll_runtime::Simulation> simulation;
    plimsoll_runtime::Water water;  ///< the bundle's own (world.water)
};

struct plimsoll_batch {
    plimsoll_eval::TaskSystem tasks;
    std::unique_ptr<plimsoll_eval::ThreadPool> pool;
    std::mutex busy;  // the pool runs one task at a time
};

namespace {

using namespace plimsoll_runtime;

thread_local std::string lastError;

void setError(std::string message) { lastError = std::move(message); }

Pose toPose(const plimsoll_pose& p) {
    Pose pose;
    pose.position = {p.position[0], p.position[1], p.position[2]};
    pose.orientation = {p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3]};
    return pose;
}

/// The caller's water. A callback that returns NaN or Inf is noted in `nonFinite` (the physics
/// would otherwise see no water there and report a finite, wrong force).
Water toWater(const plimsoll_water* w, bool* nonFinite = nullptr) {
    Water water;
    if (!w) return water;
    water.level = w->level;
    if (w->height) {
        const plimsoll_height_fn fn = w->height;
        void* user = w->user;
        water.height = [fn, user, nonFinite](double x, double z, double t) {
            const double h = fn(user, x, z, t);
            if (!std::isfinite(h) && nonFinite) *nonFinite = true;
            return h;
        };
    }
    if (w->heights) {
        const plimsoll_heights_fn fn = w->heights;
        void* user = w->user;
        water.heights = [fn, user, nonFinite](std::size_t n, const double* x, const double* z,
                                              double t, double* out) {
            fn(user, n, x, z, t, out);
            for (std::size_t i = 0; i < n && nonFinite; ++i) {
                if (!std::isfinite(out[i])) *nonFinite = true;
            }
        };
    }
    if (w->has_bounds) {
        water.minHeight = w->min_height;
        water.maxHeight = w->max_height;
    }
    if (w->velocities) {
        const plimsoll_water_velocities_fn fn = w->velocities;
        void* user = w->user;
        water.velocities = [fn, user, nonFinite](std::size_t n, const double* x, const double* y,
                                                 const double* z, double t, double* out) {
            fn(user, n, x, y, z, t, out);
            for (std::size_t i = 0; i < 3 * n && nonFinite; ++i) {
                if (!std::isfinite(out[i])) *nonFinite = true;
            }
        };
    }
    if (w->velocity) {
        const plimsoll_water_velocity_fn fn = w->velocity;
        void* user = w->user;
        water.velocity = [fn, user, nonFinite](const Vec3& p, double t) {
            const double point[3] = {p.x, p.y, p.z};
            double v[3] = {0, 0, 0};
            fn(user, point, t, v);
            if (nonFinite && !(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])))
                *nonFinite = true;
            return Vec3{v[0], v[1], v[2]};
        };
    }
    return water;
}

void copy(const Vec3& v, double out[3]) {
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
}

plimsoll_mass toC(const MassProperties& m) {
    plimsoll_mass out{};
    out.mass = m.mass;
    out.volume = m.volume;
    copy(m.centerOfMass, out.center_of_mass);
    std::memcpy(out.inertia, m.inertia, sizeof(out.inertia));
    return out;
}

Velocity toVelocity(const plimsoll_velocity* velocity) {
    Velocity v;
    if (velocity) {
        v.linear = {velocity->linear[0], velocity->linear[1], velocity->linear[2]};
        v.angular = {velocity->angular[0], velocity->angular[1], velocity->angular[2]};
    }
    return v;
}

Fluid toFluid(const plimsoll_fluid& fluid) {
    Fluid f;
    f.density = fluid.density;
    f.gravity = fluid.gravity;
    f.dragCoefficient = fluid.drag_coefficient;
    f.frictionCoefficient = fluid.friction_coefficient;
    return f;
}

void toC(const Forces& r, plimsoll_forces& out) {
    out.submerged_volume = r.submergedVolume;
    copy(r.centerOfBuoyancy, out.center_of_buoyancy);
    copy(r.force, out.force);
    copy(r.torque, out.torque);
    copy(r.pressureForce, out.pressure_force);
    copy(r.pressureTorque, out.pressure_torque);
    copy(r.dragForce, out.drag_force);
    copy(r.dragTorque, out.drag_torque);
    out.wetted_area = r.wettedArea;
    out.submerged_samples = r.submergedSamples;
}

bool hasGraph(const plimsoll_bundle* b) { return b && b->bundle && b->bundle->graph(); }

/// The 1.x calls' instance of a bundle (null for a null bundle).
plimsoll_instance* legacyOf(const plimsoll_bundle* b) { return b ? b->legacy.get() : nullptr; }

// Argument checks: a NaN, an Inf or a zero quaternion would flow through the physics and come
// back as a "successful" NaN force. Each sets the error naming the call and the argument.
bool allFinite(const double* v, int n) {
    for (int i = 0; i < n; ++i) {
        if (!std::isfinite(v[i])) return false;
    }
    return true;
}
bool refuse(const char* call, const std::string& what) {
    setError(std::string(call) + ": " + what);
    return false;
}
bool checkOrientation(const char* call, const double q[4]) {
    if (!allFinite(q, 4)) return refuse(call, "orientation has a NaN or Inf component");
    const double norm2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    if (!(norm2 > 1e-12)) return refuse(call, "orientation is a zero quaternion");
    return true;
}
bool checkPose(const char* call, const plimsoll_pose* pose) {
    if (!pose) return refuse(call, "pose is NULL");
    if (!allFinite(pose->position, 3))
        return refuse(call, "pose position has a NaN or Inf component");
    return checkOrientation(call, pose->orientation);
}
bool checkWater(const char* call, const plimsoll_water* water) {
    if (water && !std::isfinite(water->level)) return refuse(call, "water level is NaN or Inf");
    if (water && water->has_bounds &&
        !(std::isfinite(water->min_height) && std::isfinite(water->max_height) &&
          water->min_height <= water->max_height))
        return refuse(call, "water bounds must be finite with min_height <= max_height");
    return true;
}
bool checkTime(const char* call, double time) {
    if (!std::isfinite(time)) return refuse(call, "time is NaN or Inf");
    return true;
}

bool checkFluid(const char* call, const plimsoll_fluid* fluid) {
    if (fluid &&
        (!(fluid->density > 0) || !std::isfinite(fluid->density) || !(fluid->gravity >= 0) ||
         !std::isfinite(fluid->gravity) || !(fluid->drag_coefficient >= 0) ||
         !std::isfinite(fluid->drag_coefficient) || !(fluid->friction_coefficient >= 0) ||
         !std::isfinite(fluid->friction_coefficient)))
        return refuse(call,
                      "fluid: density must be finite and > 0, gravity and the "
                      "coefficients finite and >= 0");
    return true;
}

bool checkEvaluation(const char* call, const plimsoll_pose* pose, const plimsoll_velocity* velocity,
                     const plimsoll_fluid* fluid) {
    if (!checkPose(call, pose)) return false;
    if (velocity && (!allFinite(velocity->linear, 3) || !allFinite(velocity->angular, 3)))
        return refuse(call, "velocity has a NaN or Inf component");
    return checkFluid(call, fluid);
}

plimsoll_fluid defaultFluid(const Bundle& bundle) {
    const Fluid& f = bundle.fluid();
    return {f.density, f.gravity, f.dragCoefficient, f.frictionCoefficient};
}

/// Forces for checked arguments into `out`: null, or why the result is refused. Sets no
/// error, so that batch workers on other threads can call it.
const char* computeForces(const Bundle& bundle, const plimsoll_pose& pose,
                          const plimsoll_velocity* velocity, const plimsoll_water* water,
                          const plimsoll_fluid& fluid, double time, plimsoll_forces& out) {
    bool nonFiniteWater = false;
    const Forces r = bundle.evaluate(toPose(pose), toVelocity(velocity),
                                     toWater(water, &nonFiniteWater), toFluid(fluid), time);
    if (nonFiniteWater) return "the water height or velocity callback returned NaN or Inf";
    toC(r, out);
    const double* sums[] = {out.center_of_buoyancy, out.force, out.torque};
    for (const double* s : sums) {
        if (!allFinite(s, 3) || !std::isfinite(out.submerged_volume))
            return "the result is not finite (did the water height or velocity callback return "
                   "NaN or Inf?)";
    }
    return nullptr;
}

/// plimsoll_bundle_water_load for checked arguments: null, or why the result is refused.
const char* computeLoad(const Body& body, const plimsoll_pose& pose,
                        const plimsoll_velocity* velocity, const plimsoll_water* water,
                        const plimsoll_fluid& fluid, double time, double dt, plimsoll_load& out) {
    bool nonFiniteWater = false;
    const WaterLoad load = waterLoad(body, toPose(pose), toVelocity(velocity),
                                     toWater(water, &nonFiniteWater), toFluid(fluid), time, dt);
    if (nonFiniteWater) return "the water height or velocity callback returned NaN or Inf";
    copy(load.force, out.force);
    copy(load.torque, out.torque);
    out.water_mass = load.waterMass;
    toC(load.forces, out.forces);
    if (!allFinite(out.force, 3) || !allFinite(out.torque, 3)) return "the result is not finite";
    return nullptr;
}

bool present(const plimsoll_bundle* b) { return b && b->bundle; }
bool present(const plimsoll_instance* i) { return i != nullptr; }

/// Each body of a batch call (a bundle or an instance): present, a finite pose with a non-zero
/// quaternion, a finite velocity. The message, naming the body, is only built for one that
/// fails.
template <class Handle>
bool checkBodies(const char* call, std::size_t count, const Handle* const* bodies,
                 const plimsoll_pose* poses, const plimsoll_velocity* velocities) {
    for (std::size_t i = 0; i < count; ++i) {
        const plimsoll_velocity* velocity = velocities ? &velocities[i] : nullptr;
        const double* q = poses[i].orientation;
        const bool fine =
            present(bodies[i]) && allFinite(poses[i].position, 3) && allFinite(q, 4) &&
            q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] > 1e-12 &&
            (!velocity || (allFinite(velocity->linear, 3) && allFinite(velocity->angular, 3)));
        if (fine) continue;
        const std::string item = std::string(call) + ": body " + std::to_string(i);
        if (!present(bodies[i])) return refuse(item.c_str(), "bundle is NULL");
        return checkEvaluation(item.c_str(), &poses[i], velocity, nullptr);
    }
    return true;
}

/// No handle twice in one call that changes their state (two workers would race on it).
template <class Handle>
bool distinct(const char* call, std::size_t count, const Handle* const* bodies, const char* what) {
    std::vector<const Handle*> sorted(bodies, bodies + count);
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return refuse(call, what);
    return true;
}

/// The arguments every batch evaluation shares, checked on the calling thread.
template <class Handle>
bool checkBatch(const char* call, const plimsoll_batch* batch, std::size_t count,
                const Handle* const* bodies, const plimsoll_pose* poses,
                const plimsoll_velocity* velocities, const void* out, const plimsoll_water* water,
                const plimsoll_fluid* fluid, double time) {
    if (!batch || (count > 0 && (!bodies || !poses || !out)))
        return refuse(call, "batch, bodies, poses or out is NULL");
    if (count > static_cast<std::size_t>(INT32_MAX))
        return refuse(call, "more than 2^31 - 1 bodies");
    if (!checkWater(call, water) || !checkTime(call, time) || !checkFluid(call, fluid))
        return false;
    return checkBodies(call, count, bodies, poses, velocities);
}

/// Runs body(i) for i < count on the batch's task system or pool; each failure is kept with
/// its index and the lowest one is reported, as a single call would have reported it.
///
/// A batch runs one call at a time, so a call made from inside its own work (a water callback
/// evaluating the same batch) would wait for itself forever. Every item runs with the chain of
/// batches whose calls it works for (on whichever thread, the pool's, the caller's task
/// system's or the caller's own), so such a call, direct or through other batches, is refused.
thread_local const std::vector<const plimsoll_batch*>* runningBatches = nullptr;

template <class Body>
bool runBatch(plimsoll_batch& batch, const char* call, std::size_t count, Body&& body) {
    if (count == 0) return true;
    std::vector<const plimsoll_batch*> chain;
    if (runningBatches) chain = *runningBatches;
    if (std::find(chain.begin(), chain.end(), &batch) != chain.end())
        return refuse(call,
                      "the batch is busy with the call this one was made from (a callback of "
                      "its work called it again), which would wait for itself: refused");
    chain.push_back(&batch);
    std::atomic<std::size_t> firstFailure{count};
    std::vector<const char*> failures(count, nullptr);
    auto item = [&](int i, std::uint32_t) {
        const std::vector<const plimsoll_batch*>* const outer = runningBatches;
        runningBatches = &chain;
        struct Restore {
            const std::vector<const plimsoll_batch*>* outer;
            ~Restore() { runningBatches = outer; }
        } restore{outer};
        try {
            failures[i] = body(static_cast<std::size_t>(i));
        } catch (const std::exception&) {
            failures[i] = "internal error (an exception in the runtime)";
        }
        if (failures[i]) {
            std::size_t seen = firstFailure.load();
            while (static_cast<std::size_t>(i) < seen &&
                   !firstFailure.compare_exchange_weak(seen, i)) {
            }
        }
    };
    {
        std::lock_guard<std::mutex> lock(batch.busy);
        plimsoll_eval::parallelFor(static_cast<int>(count), 1, batch.tasks, *batch.pool, item);
    }
    const std::size_t first = firstFailure.load();
    if (first == count) return true;
    return refuse(call, "body " + std::to_string(first) + ": " + failures[first]);
}

}  // namespace

extern "C" {

const char* plimsoll_runtime_last_error(void) { return lastError.c_str(); }

const char* plimsoll_runtime_schema_version(void) {
    lastError.clear();
    static const std::string version = std::to_string(bundleSchemaVersion().major) + "." +
                                       std::to_string(bundleSchemaVersion().minor);
    return version.c_str();
}

void plimsoll_runtime_version(int* major, int* minor, int* patch) {
    lastError.clear();
    const Version v = runtimeVersion();
    if (major) *major = v.major;
    if (minor) *minor = v.minor;
    if (patch) *patch = v.patch;
}

void plimsoll_quaternion_from_xyzw(const double xyzw[4], double wxyz[4]) {
    lastError.clear();
    if (!xyzw || !wxyz) {
        refuse("plimsoll_quaternion_from_xyzw", "an argument is NULL");
        return;
    }
    const double q[4] = {xyzw[3], xyzw[0], xyzw[1], xyzw[2]};
    std::memcpy(wxyz, q, sizeof q);
}

void plimsoll_quaternion_to_xyzw(const double wxyz[4], double xyzw[4]) {
    lastError.clear();
    if (!wxyz || !xyzw) {
        refuse("plimsoll_quaternion_to_xyzw", "an argument is NULL");
        return;
    }
    const double q[4] = {wxyz[1], wxyz[2], wxyz[3], wxyz[0]};
    std::memcpy(xyzw, q, sizeof q);
}

void plimsoll_runtime_bundle_schema(int* major, int* minor) {
    lastError.clear();
    const Version v = bundleSchemaVersion();
    if (major) *major = v.major;
    if (minor) *minor = v.minor;
}

}  // extern "C"

namespace {

/// The handle for what a loader returned, or null with the loader's error.
template <class Load>
plimsoll_bundle* loadHandle(const char* call, Load&& load) {
    try {
        std::string error;
        auto bundle = load(error);
        if (!bundle) {
            setError(error);
            return nullptr;
        }
        auto handle = std::make_unique<plimsoll_bundle>();
        handle->bundle = std::move(bundle);
        handle->legacy.reset(new plimsoll_instance{handle.get(), Body(*handle->bundle)});
        lastError.clear();
        return handle.release();
    } catch (const std::exception& e) {
        setError(std::string(call) + ": " + e.what());
        return nullptr;
    }
}

LoadOptions loadOptions(int verifyChecksums) {
    LoadOptions options;
    options.verifyChecksums = verifyChecksums != 0;
    return options;
}

}  // namespace

extern "C" {

plimsoll_bundle* plimsoll_bundle_load(const char* folder, int verify_checksums) {
    lastError.clear();
    if (!folder) {
        setError("plimsoll_bundle_load: folder is NULL");
        return nullptr;
    }
    return loadHandle("plimsoll_bundle_load", [&](std::string& error) {
        return loadBundle(folder, error, loadOptions(verify_checksums));
    });
}

plimsoll_bundle* plimsoll_bundle_load_memory(const plimsoll_memory_file* files, size_t count,
                                             const char* name, int verify_checksums) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_bundle_load_memory";
    if (!files && count > 0) {
        refuse(kCall, "files is NULL");
        return nullptr;
    }
    std::vector<MemoryFile> list(count);
    for (std::size_t i = 0; i < count; ++i) {
        if (!files[i].path) {
            refuse(kCall, "file " + std::to_string(i) + ": path is NULL");
            return nullptr;
        }
        list[i] = {files[i].path, files[i].data, files[i].size};
    }
    return loadHandle(kCall, [&](std::string& error) {
        return loadBundleFromMemory(list, name ? name : "memory", error,
                                    loadOptions(verify_checksums));
    });
}

plimsoll_bundle* plimsoll_bundle_load_callbacks(const plimsoll_file_callbacks* callbacks,
                                                const char* name, int verify_checksums) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_bundle_load_callbacks";
    if (!callbacks || callbacks->struct_size < sizeof(plimsoll_file_callbacks) ||
        !callbacks->open || !callbacks->size || !callbacks->read || !callbacks->close) {
        refuse(kCall,
               "callbacks is NULL, its struct_size is not sizeof(plimsoll_file_callbacks) "
               "or open, size, read or close is NULL");
        return nullptr;
    }
    const plimsoll_file_callbacks c = *callbacks;
    FileCallbacks cpp;
    cpp.open = [c](const std::string& path) { return c.open(c.user, path.c_str()); };
    cpp.size = [c](void* file) { return static_cast<long long>(c.size(c.user, file)); };
    cpp.read = [c](void* file, std::uint64_t offset, void* buffer, std::size_t bytes) {
        return static_cast<long long>(c.read(c.user, file, offset, buffer, bytes));
    };
    cpp.close = [c](void* file) { c.close(c.user, file); };
    return loadHandle(kCall, [&](std::string& error) {
        return loadBundleWithCallbacks(cpp, name ? name : "callbacks", error,
                                       loadOptions(verify_checksums));
    });
}

int plimsoll_bundle_size_query(const plimsoll_bundle* bundle, plimsoll_bundle_size* out) {
    lastError.clear();
    if (!bundle || !out || out->struct_size < sizeof(plimsoll_bundle_size))
        return refuse(
            "plimsoll_bundle_size_query",
            "bundle or out is NULL, or out->struct_size is not sizeof(plimsoll_bundle_size)");
    const Bundle& b = *bundle->bundle;
    out->file_bytes = b.fileBytes();
    out->memory_bytes = b.memoryBytes();
    out->samples = b.samples().size();
    out->graph_nodes = b.graph() ? b.graph()->nodes().size() : 0;
    return 1;
}

void plimsoll_bundle_destroy(plimsoll_bundle* bundle) {
    // Leaves the last error: freeing what a failed call returned comes before reading why.
    delete bundle;
}

void plimsoll_bundle_free(plimsoll_bundle* bundle) { plimsoll_bundle_destroy(bundle); }

const char* plimsoll_bundle_body(const plimsoll_bundle* bundle) {
    lastError.clear();
    return bundle && bundle->bundle ? bundle->bundle->body().c_str() : "";
}

size_t plimsoll_bundle_sample_count(const plimsoll_bundle* bundle) {
    lastError.clear();
    return bundle ? bundle->bundle->samples().size() : 0;
}

plimsoll_mass plimsoll_bundle_mass(const plimsoll_bundle* bundle) {
    lastError.clear();
    if (!bundle) {
        refuse("plimsoll_bundle_mass", "bundle is NULL");
        return plimsoll_mass{};
    }
    return toC(bundle->bundle->mass());
}

plimsoll_fluid plimsoll_bundle_default_fluid(const plimsoll_bundle* bundle) {
    lastError.clear();
    if (!bundle) refuse("plimsoll_bundle_default_fluid", "bundle is NULL");
    return bundle ? defaultFluid(*bundle->bundle) : plimsoll_fluid{1000.0, 9.81, 1.0, 0.0};
}

void plimsoll_bundle_damping(const plimsoll_bundle* bundle, double* linear, double* angular) {
    lastError.clear();
    if (linear) *linear = bundle ? bundle->bundle->linearDamping() : 0.0;
    if (angular) *angular = bundle ? bundle->bundle->angularDamping() : 0.0;
}

int plimsoll_bundle_evaluate(const plimsoll_bundle* bundle, const plimsoll_pose* pose,
                             const plimsoll_velocity* velocity, const plimsoll_water* water,
                             const plimsoll_fluid* fluid, double time, plimsoll_forces* out) {
    lastError.clear();
    try {
        constexpr const char* kCall = "plimsoll_bundle_evaluate";
        if (!bundle || !pose || !fluid || !out) {
            setError("plimsoll_bundle_evaluate: a required argument is NULL");
            return 0;
        }
        if (!checkEvaluation(kCall, pose, velocity, fluid) || !checkWater(kCall, water) ||
            !checkTime(kCall, time))
            return 0;
        const char* failure =
            computeForces(*bundle->bundle, *pose, velocity, water, *fluid, time, *out);
        return failure ? refuse(kCall, failure) : 1;
    } catch (const std::exception& e) {
        setError(std::string("plimsoll_bundle_evaluate: ") + e.what());
        return 0;
    }
}

size_t plimsoll_graph_node_count(const plimsoll_bundle* bundle) {
    lastError.clear();
    return hasGraph(bundle) ? bundle->bundle->graph()->nodes().size() : 0;
}

}  // extern "C"

namespace {

/// The instance's water graph and node, or null with the error set (naming `call`).
const WaterGraph* graphNode(const char* call, const plimsoll_instance* instance, std::size_t node) {
    if (!instance) {
        refuse(call, "instance is NULL");
        return nullptr;
    }
    const WaterGraph* graph = instance->body.graph();
    if (!graph) {
        refuse(call, "the body has no water graph");
        return nullptr;
    }
    if (node >= graph->nodeCount()) {
        refuse(call, "no such node: " + std::to_string(node) + " of " +
                         std::to_string(graph->nodeCount()));
        return nullptr;
    }
    return graph;
}

int nodeWater(const char* call, const plimsoll_instance* instance, std::size_t node,
              double* water) {
    if (!water) return refuse(call, "water is NULL");
    const WaterGraph* graph = graphNode(call, instance, node);
    if (!graph) return 0;
    *water = graph->water(node);
    return 1;
}

int setNodeWater(const char* call, plimsoll_instance* instance, std::size_t node, double water) {
    if (!graphNode(call, instance, node)) return 0;
    if (!(water >= 0) || !(water <= instance->bundle->bundle->graph()->nodes()[node].capacity))
        return refuse(call, "water must be in 0..the node's capacity");
    instance->body.graph()->setWater(node, water);
    return 1;
}

int setMedium(const char* call, plimsoll_instance* instance, double density, double viscosity,
              double gravity) {
    if (!instance) return refuse(call, "instance is NULL");
    if (!instance->body.graph()) return refuse(call, "the body has no water graph");
    if (!(density > 0) || !(viscosity > 0) || !(gravity >= 0) || !std::isfinite(density) ||
        !std::isfinite(viscosity) || !std::isfinite(gravity))
        return refuse(call, "density and viscosity must be > 0, gravity >= 0");
    instance->body.graph()->setMedium(density, viscosity, gravity);
    return 1;
}

int graphInflow(const char* call, const plimsoll_instance* instance, const plimsoll_pose* pose,
                const plimsoll_water* water, double time, double* inflow, double* outflow) {
    try {
        if (!instance || !instance->body.graph() || !pose)
            return refuse(call, "no water graph or no pose");
        if (!checkPose(call, pose) || !checkWater(call, water) || !checkTime(call, time)) return 0;
        bool nonFinite = false;
        const NodeInflow r =
            instance->body.graph()->inflow(toPose(*pose), toWater(water, &nonFinite), time);
        if (nonFinite) return refuse(call, "the water height callback returned NaN or Inf");
        for (std::size_t i = 0; i < r.inflow.size(); ++i) {
            if (inflow) inflow[i] = r.inflow[i];
            if (outflow) outflow[i] = r.outflow[i];
        }
        return 1;
    } catch (const std::exception& e) {
        return refuse(call, e.what());
    }
}

/// One graph step of checked arguments: 1 moved, 0 not, -1 and the error.
int graphStep(const char* call, plimsoll_instance* instance, const plimsoll_pose* pose,
              const plimsoll_water* water, double time, double dt, bool needsGraph) {
    try {
        if (!instance || !pose || !(dt >= 0) || !std::isfinite(dt)) {
            refuse(call, "no instance, no pose, or dt not finite and >= 0");
            return -1;
        }
        if (needsGraph && !instance->body.graph()) {
            refuse(call, "the body has no water graph");
            return -1;
        }
        if (!checkPose(call, pose) || !checkWater(call, water) || !checkTime(call, time)) return -1;
        WaterGraph* graph = instance->body.graph();
        if (!graph) return 0;
        // A step that meets a NaN height is undone: the state stays as it was.
        instance->undo.clear();
        graph->saveState(instance->undo);
        bool nonFinite = false;
        const bool moved = graph->step(toPose(*pose), toWater(water, &nonFinite), time, dt);
        if (nonFinite) {
            std::size_t at = 0;
            graph->restoreState(instance->undo, at);
            refuse(call, "the water height callback returned NaN or Inf");
            return -1;
        }
        return moved ? 1 : 0;
    } catch (const std::exception& e) {
        refuse(call, e.what());
        return -1;
    }
}

int waterMassOf(const char* call, const plimsoll_instance* instance, const double orientation[4],
                plimsoll_mass* out) {
    if (!instance || !orientation || !out)
        return refuse(call, "instance, orientation or out is NULL");
    if (!instance->body.graph()) return refuse(call, "the body has no water graph");
    if (!checkOrientation(call, orientation)) return 0;
    try {
        *out = toC(instance->body.graph()->waterMass(
            {orientation[0], orientation[1], orientation[2], orientation[3]}));
        return 1;
    } catch (const std::exception& e) {
        return refuse(call, e.what());
    }
}

}  // namespace

extern "C" {

double plimsoll_graph_node_water(const plimsoll_bundle* bundle, size_t node) {
    lastError.clear();
    double water = 0.0;
    nodeWater("plimsoll_graph_node_water", legacyOf(bundle), node, &water);
    return water;
}

double plimsoll_graph_node_capacity(const plimsoll_bundle* bundle, size_t node) {
    lastError.clear();
    if (!hasGraph(bundle) || node >= plimsoll_graph_node_count(bundle)) {
        refuse("plimsoll_graph_node_capacity",
               !hasGraph(bundle) ? std::string("the body has no water graph")
                                 : "node " + std::to_string(node) + " of " +
                                       std::to_string(plimsoll_graph_node_count(bundle)));
        return 0.0;
    }
    return bundle->bundle->graph()->nodes()[node].capacity;
}

int plimsoll_graph_set_node_water(plimsoll_bundle* bundle, size_t node, double water) {
    lastError.clear();
    return setNodeWater("plimsoll_graph_set_node_water", legacyOf(bundle), node, water);
}

int plimsoll_graph_set_medium(plimsoll_bundle* bundle, double density, double viscosity,
                              double gravity) {
    lastError.clear();
    return setMedium("plimsoll_graph_set_medium", legacyOf(bundle), density, viscosity, gravity);
}

int plimsoll_graph_inflow(const plimsoll_bundle* bundle, const plimsoll_pose* pose,
                          const plimsoll_water* water, double time, double* inflow,
                          double* outflow) {
    lastError.clear();
    return graphInflow("plimsoll_graph_inflow", legacyOf(bundle), pose, water, time, inflow,
                       outflow);
}

int plimsoll_graph_step(plimsoll_bundle* bundle, const plimsoll_pose* pose,
                        const plimsoll_water* water, double time, double dt) {
    lastError.clear();
    return graphStep("plimsoll_graph_step", legacyOf(bundle), pose, water, time, dt, true);
}

plimsoll_mass plimsoll_graph_water_mass(const plimsoll_bundle* bundle,
                                        const double orientation[4]) {
    lastError.clear();
    plimsoll_mass out{};
    waterMassOf("plimsoll_graph_water_mass", legacyOf(bundle), orientation, &out);
    return out;
}

int plimsoll_bundle_bounds(const plimsoll_bundle* bundle, double min[3], double max[3]) {
    lastError.clear();
    if (!bundle || !min || !max) return refuse("plimsoll_bundle_bounds", "an argument is NULL");
    const auto& samples = bundle->bundle->samples();
    if (samples.empty()) return refuse("plimsoll_bundle_bounds", "the bundle has no samples");
    Vec3 lo = samples.front().position, hi = lo;
    for (const Sample& s : samples) {
        lo = {std::min(lo.x, s.position.x), std::min(lo.y, s.position.y),
              std::min(lo.z, s.position.z)};
        hi = {std::max(hi.x, s.position.x), std::max(hi.y, s.position.y),
              std::max(hi.z, s.position.z)};
    }
    copy(lo, min);
    copy(hi, max);
    return 1;
}

}  // extern "C"

namespace {

int instanceWaterLoad(const char* call, const plimsoll_instance* instance,
                      const plimsoll_pose* pose, const plimsoll_velocity* velocity,
                      const plimsoll_water* water, const plimsoll_fluid* fluid, double time,
                      double dt, plimsoll_load* out) {
    try {
        if (!instance || !pose || !fluid || !out)
            return refuse(call, "a required argument is NULL");
        if (!checkEvaluation(call, pose, velocity, fluid) || !checkWater(call, water) ||
            !checkTime(call, time))
            return 0;
        if (!(dt > 0) || !std::isfinite(dt)) return refuse(call, "dt must be finite and > 0");
        const char* failure =
            computeLoad(instance->body, *pose, velocity, water, *fluid, time, dt, *out);
        return failure ? refuse(call, failure) : 1;
    } catch (const std::exception& e) {
        return refuse(call, e.what());
    }
}

/// One step of a body on its own, with `memory`'s radiation (none when null), for checked
/// arguments: null, or why it was refused. Sets no error (batch workers call it); the state,
/// the water and the memory change only when the step's result is finite. `sleeps`: the 2.0
/// calls, whose instances sleep at rest (stepBody); the 1.x calls never did.
const char* stepInstance(plimsoll_instance& instance, plimsoll_body_state& state,
                         RadiationMemory* memory, const plimsoll_water* water,
                         const plimsoll_fluid& fluid, double time, double dt, bool sleeps) {
    BodyState s{toPose(state.pose), toVelocity(&state.velocity)};
    bool nonFiniteWater = false;
    instance.body.save(instance.undo);
    // A memory of the body's own is in its snapshot; a 1.x caller's own memory is copied.
    std::optional<RadiationMemory> memoryBefore;
    if (memory && memory != instance.body.radiation()) memoryBefore = *memory;
    if (sleeps)
        stepBody(instance.body, s, toWater(water, &nonFiniteWater), toFluid(fluid), time, dt);
    else
        stepBodyWith(instance.body, s, memory, toWater(water, &nonFiniteWater), toFluid(fluid),
                     time, dt);
    const double next[13] = {s.pose.position.x,    s.pose.position.y,    s.pose.position.z,
                             s.pose.orientation.w, s.pose.orientation.x, s.pose.orientation.y,
                             s.pose.orientation.z, s.velocity.linear.x,  s.velocity.linear.y,
                             s.velocity.linear.z,  s.velocity.angular.x, s.velocity.angular.y,
                             s.velocity.angular.z};
    const char* refused =
        nonFiniteWater         ? "the water height or velocity callback returned NaN or Inf"
        : !allFinite(next, 13) ? "the new state is not finite (state left as it was)"
                               : nullptr;
    if (refused) {
        std::string ignored;
        instance.body.restore(instance.undo, ignored);
        if (memoryBefore) *memory = *memoryBefore;
        return refused;
    }
    copy(s.pose.position, state.pose.position);
    state.pose.orientation[0] = s.pose.orientation.w;
    state.pose.orientation[1] = s.pose.orientation.x;
    state.pose.orientation[2] = s.pose.orientation.y;
    state.pose.orientation[3] = s.pose.orientation.z;
    copy(s.velocity.linear, state.velocity.linear);
    copy(s.velocity.angular, state.velocity.angular);
    return nullptr;
}

/// RadiationMemory::begin for checked arguments, into the C struct.
int radiationBegin(const char* call, RadiationMemory& memory, const plimsoll_pose* pose,
                   double submergedVolume, plimsoll_radiation_load* out) {
    if (!checkPose(call, pose)) return 0;
    if (!(submergedVolume >= 0) || !std::isfinite(submergedVolume))
        return refuse(call, "submerged_volume must be finite and >= 0");
    const RadiationLoad load = memory.begin(toPose(*pose), submergedVolume);
    out->share = load.share;
    out->previous_share = load.previousShare;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            out->added_mass[i][j] = load.addedMass[i][j];
            out->added_inertia[i][j] = load.addedInertia[i][j];
        }
    }
    copy(load.force, out->force);
    copy(load.torque, out->torque);
    return 1;
}

int radiationAdvance(const char* call, RadiationMemory& memory, const plimsoll_pose* pose,
                     const plimsoll_velocity* velocity, double dt) {
    if (!checkPose(call, pose)) return 0;
    if (!allFinite(velocity->linear, 3) || !allFinite(velocity->angular, 3))
        return refuse(call, "velocity has a NaN or Inf component");
    if (!(dt > 0) || !std::isfinite(dt)) return refuse(call, "dt must be finite and > 0");
    memory.advance(toPose(*pose), toVelocity(velocity), dt);
    return 1;
}

/// A snapshot into the caller's buffer: *size always, the bytes when they fit.
int copySnapshot(const char* call, const std::vector<std::uint8_t>& bytes, void* buffer,
                 std::size_t capacity, std::size_t* size) {
    *size = bytes.size();
    if (!buffer) return 1;
    if (capacity < bytes.size())
        return refuse(call, "capacity " + std::to_string(capacity) + " is less than the " +
                                std::to_string(bytes.size()) + " bytes of the snapshot");
    std::memcpy(buffer, bytes.data(), bytes.size());
    return 1;
}

/// restore() of a simulation or an instance from the caller's bytes; nothing changes on failure.
template <class Target>
int restoreSnapshot(const char* call, Target* target, const void* bytes, std::size_t size) {
    try {
        if (!target || (!bytes && size > 0)) return refuse(call, "a required argument is NULL");
        const auto* p = static_cast<const std::uint8_t*>(bytes);
        std::string error;
        if (!target->restore(std::vector<std::uint8_t>(p, p + size), error))
            return refuse(call, error);
        return 1;
    } catch (const std::exception& e) {
        return refuse(call, e.what());
    }
}

/// stateHash() of a simulation or an instance; 0 and the error for a null `what`.
template <class Target>
std::uint64_t stateHashOf(const char* call, const char* what, const Target* target) {
    try {
        if (!target) {
            refuse(call, std::string(what) + " is NULL");
            return 0;
        }
        return target->stateHash();
    } catch (const std::exception& e) {
        refuse(call, e.what());
        return 0;
    }
}

/// The checks of a step call, then the step.
int stepChecked(const char* call, plimsoll_instance* instance, plimsoll_body_state* state,
                RadiationMemory* memory, const plimsoll_water* water, const plimsoll_fluid* fluid,
                double time, double dt, bool sleeps) {
    try {
        if (!instance || !state || !fluid) return refuse(call, "a required argument is NULL");
        if (!checkEvaluation(call, &state->pose, &state->velocity, fluid) ||
            !checkWater(call, water) || !checkTime(call, time))
            return 0;
        if (!(dt > 0) || !std::isfinite(dt)) return refuse(call, "dt must be finite and > 0");
        const char* refused =
            stepInstance(*instance, *state, memory, water, *fluid, time, dt, sleeps);
        return refused ? refuse(call, refused) : 1;
    } catch (const std::exception& e) {
        return refuse(call, e.what());
    }
}

}  // namespace

extern "C" {

int plimsoll_bundle_water_load(const plimsoll_bundle* bundle, const plimsoll_pose* pose,
                               const plimsoll_velocity* velocity, const plimsoll_water* water,
                               const plimsoll_fluid* fluid, double time, double dt,
                               plimsoll_load* out) {
    lastError.clear();
    return instanceWaterLoad("plimsoll_bundle_water_load", legacyOf(bundle), pose, velocity, water,
                             fluid, time, dt, out);
}

int plimsoll_body_step(plimsoll_bundle* bundle, plimsoll_body_state* state,
                       const plimsoll_water* water, const plimsoll_fluid* fluid, double time,
                       double dt) {
    lastError.clear();
    return stepChecked("plimsoll_body_step", legacyOf(bundle), state, nullptr, water, fluid, time,
                       dt, false);
}

int plimsoll_body_step_radiating(plimsoll_bundle* bundle, plimsoll_body_state* state,
                                 plimsoll_radiation_memory* memory, const plimsoll_water* water,
                                 const plimsoll_fluid* fluid, double time, double dt) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_body_step_radiating";
    if (!memory) return refuse(kCall, "memory is NULL");
    if (bundle && memory->bundle != bundle->bundle.get())
        return refuse(kCall, "the radiation memory was made for another bundle");
    return stepChecked(kCall, legacyOf(bundle), state, &memory->memory, water, fluid, time, dt,
                       false);
}

int plimsoll_bundle_radiation(const plimsoll_bundle* bundle, plimsoll_radiation_info* out) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_bundle_radiation";
    if (!bundle || !bundle->bundle || !out) return refuse(kCall, "a required argument is NULL");
    const Radiation* r = bundle->bundle->radiation();
    if (!r) return refuse(kCall, "the body was exported without radiation");
    out->rest_volume = r->restVolume;
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) out->added_mass_infinity[i][j] = r->addedMassInfinity[i][j];
        out->memory_terms[i] = static_cast<int>(r->memory[i].size());
    }
    return 1;
}

plimsoll_radiation_memory* plimsoll_radiation_memory_create(const plimsoll_bundle* bundle) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_radiation_memory_create";
    try {
        if (!bundle || !bundle->bundle) {
            refuse(kCall, "bundle is NULL");
            return nullptr;
        }
        const Radiation* r = bundle->bundle->radiation();
        if (!r) {
            refuse(kCall, "the body was exported without radiation");
            return nullptr;
        }
        return new plimsoll_radiation_memory{bundle->bundle.get(), RadiationMemory(r)};
    } catch (const std::exception& e) {
        refuse(kCall, e.what());
        return nullptr;
    }
}

void plimsoll_radiation_memory_destroy(plimsoll_radiation_memory* memory) {
    // Leaves the last error: freeing what a failed call returned comes before reading why.
    delete memory;
}

int plimsoll_radiation_memory_begin(plimsoll_radiation_memory* memory, const plimsoll_pose* pose,
                                    double submerged_volume, plimsoll_radiation_load* out) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_radiation_memory_begin";
    if (!memory || !out) return refuse(kCall, "a required argument is NULL");
    return radiationBegin(kCall, memory->memory, pose, submerged_volume, out);
}

int plimsoll_radiation_memory_advance(plimsoll_radiation_memory* memory, const plimsoll_pose* pose,
                                      const plimsoll_velocity* velocity, double dt) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_radiation_memory_advance";
    if (!memory || !velocity) return refuse(kCall, "a required argument is NULL");
    return radiationAdvance(kCall, memory->memory, pose, velocity, dt);
}

double plimsoll_radiation_memory_energy(const plimsoll_radiation_memory* memory) {
    lastError.clear();
    return memory ? memory->memory.energy() : 0.0;
}

plimsoll_batch* plimsoll_batch_create(const plimsoll_batch_desc* desc) {
    lastError.clear();
    try {
        if (desc && desc->struct_size < sizeof(plimsoll_batch_desc)) {
            setError("plimsoll_batch_create: desc->struct_size is not sizeof(plimsoll_batch_desc)");
            return nullptr;
        }
        if (desc && (desc->enqueue != nullptr) != (desc->finish != nullptr)) {
            setError("plimsoll_batch_create: give both enqueue and finish, or neither");
            return nullptr;
        }
        if (desc && desc->thread_count < 0) {
            setError("plimsoll_batch_create: thread_count must be >= 0");
            return nullptr;
        }
        auto batch = std::make_unique<plimsoll_batch>();
        int threads = desc ? desc->thread_count : 0;
        if (desc && desc->enqueue) {
            batch->tasks.enqueue = desc->enqueue;
            batch->tasks.finish = desc->finish;
            batch->tasks.userContext = desc->user_context;
            batch->tasks.workerCount = std::max(1, desc->worker_count);
            threads = 1;  // the pool is not used
        }
        if (threads == 0)
            threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
        batch->pool = std::make_unique<plimsoll_eval::ThreadPool>(threads);
        return batch.release();
    } catch (const std::exception& e) {
        setError(std::string("plimsoll_batch_create: ") + e.what());
        return nullptr;
    }
}

void plimsoll_batch_destroy(plimsoll_batch* batch) {
    // Leaves the last error: freeing what a failed call returned comes before reading why.
    delete batch;
}

void plimsoll_batch_free(plimsoll_batch* batch) { plimsoll_batch_destroy(batch); }

int plimsoll_batch_evaluate(plimsoll_batch* batch, size_t count,
                            const plimsoll_bundle* const* bodies, const plimsoll_pose* poses,
                            const plimsoll_velocity* velocities, const plimsoll_water* water,
                            const plimsoll_fluid* fluid, double time, plimsoll_forces* out) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_batch_evaluate";
    try {
        if (!checkBatch(kCall, batch, count, bodies, poses, velocities, out, water, fluid, time))
            return 0;
        return runBatch(*batch, kCall, count,
                        [&](std::size_t i) {
                            const Bundle& b = *bodies[i]->bundle;
                            const plimsoll_fluid f = fluid ? *fluid : defaultFluid(b);
                            return computeForces(b, poses[i], velocities ? &velocities[i] : nullptr,
                                                 water, f, time, out[i]);
                        })
                   ? 1
                   : 0;
    } catch (const std::exception& e) {
        return refuse(kCall, e.what());
    }
}

int plimsoll_batch_water_load(plimsoll_batch* batch, size_t count,
                              const plimsoll_bundle* const* bodies, const plimsoll_pose* poses,
                              const plimsoll_velocity* velocities, const plimsoll_water* water,
                              const plimsoll_fluid* fluid, double time, double dt,
                              plimsoll_load* out) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_batch_water_load";
    try {
        if (!checkBatch(kCall, batch, count, bodies, poses, velocities, out, water, fluid, time))
            return 0;
        if (!(dt > 0) || !std::isfinite(dt)) return refuse(kCall, "dt must be finite and > 0");
        return runBatch(*batch, kCall, count,
                        [&](std::size_t i) {
                            const plimsoll_instance& instance = *bodies[i]->legacy;
                            const plimsoll_fluid f =
                                fluid ? *fluid : defaultFluid(*bodies[i]->bundle);
                            return computeLoad(instance.body, poses[i],
                                               velocities ? &velocities[i] : nullptr, water, f,
                                               time, dt, out[i]);
                        })
                   ? 1
                   : 0;
    } catch (const std::exception& e) {
        return refuse(kCall, e.what());
    }
}

int plimsoll_batch_graph_step(plimsoll_batch* batch, size_t count, plimsoll_bundle* const* bodies,
                              const plimsoll_pose* poses, const plimsoll_water* water, double time,
                              double dt, int* moved) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_batch_graph_step";
    try {
        if (!batch || (count > 0 && (!bodies || !poses)))
            return refuse(kCall, "batch, bodies or poses is NULL");
        if (count > static_cast<size_t>(INT32_MAX))
            return refuse(kCall, "more than 2^31 - 1 bodies");
        if (!checkWater(kCall, water) || !checkTime(kCall, time)) return 0;
        if (!(dt >= 0) || !std::isfinite(dt)) return refuse(kCall, "dt must be finite and >= 0");
        if (!checkBodies(kCall, count, bodies, poses, nullptr) ||
            !distinct(kCall, count, bodies,
                      "a bundle appears twice (each graph steps once per call)"))
            return 0;
        return runBatch(*batch, kCall, count,
                        [&](std::size_t i) -> const char* {
                            WaterGraph* graph = bodies[i]->legacy->body.graph();
                            const bool changed =
                                graph && graph->step(toPose(poses[i]), toWater(water), time, dt);
                            if (moved) moved[i] = changed ? 1 : 0;
                            return nullptr;
                        })
                   ? 1
                   : 0;
    } catch (const std::exception& e) {
        return refuse(kCall, e.what());
    }
}

int plimsoll_batch_instance_water_load(plimsoll_batch* batch, size_t count,
                                       const plimsoll_instance* const* instances,
                                       const plimsoll_pose* poses,
                                       const plimsoll_velocity* velocities,
                                       const plimsoll_water* water, const plimsoll_fluid* fluid,
                                       double time, double dt, plimsoll_load* out) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_batch_instance_water_load";
    try {
        if (!checkBatch(kCall, batch, count, instances, poses, velocities, out, water, fluid, time))
            return 0;
        if (!(dt > 0) || !std::isfinite(dt)) return refuse(kCall, "dt must be finite and > 0");
        return runBatch(*batch, kCall, count,
                        [&](std::size_t i) {
                            const plimsoll_instance& instance = *instances[i];
                            const plimsoll_fluid f =
                                fluid ? *fluid : defaultFluid(instance.body.bundle());
                            return computeLoad(instance.body, poses[i],
                                               velocities ? &velocities[i] : nullptr, water, f,
                                               time, dt, out[i]);
                        })
                   ? 1
                   : 0;
    } catch (const std::exception& e) {
        return refuse(kCall, e.what());
    }
}

int plimsoll_batch_instance_graph_step(plimsoll_batch* batch, size_t count,
                                       plimsoll_instance* const* instances,
                                       const plimsoll_pose* poses, const plimsoll_water* water,
                                       double time, double dt, int* moved) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_batch_instance_graph_step";
    try {
        if (!batch || (count > 0 && (!instances || !poses)))
            return refuse(kCall, "batch, instances or poses is NULL");
        if (count > static_cast<size_t>(INT32_MAX))
            return refuse(kCall, "more than 2^31 - 1 bodies");
        if (!checkWater(kCall, water) || !checkTime(kCall, time)) return 0;
        if (!(dt >= 0) || !std::isfinite(dt)) return refuse(kCall, "dt must be finite and >= 0");
        if (!checkBodies(kCall, count, instances, poses, nullptr) ||
            !distinct(kCall, count, instances,
                      "an instance appears twice (each steps once per call)"))
            return 0;
        return runBatch(*batch, kCall, count,
                        [&](std::size_t i) -> const char* {
                            WaterGraph* graph = instances[i]->body.graph();
                            bool nonFinite = false;
                            const bool changed =
                                graph &&
                                graph->step(toPose(poses[i]), toWater(water, &nonFinite), time, dt);
                            if (moved) moved[i] = changed ? 1 : 0;
                            return nonFinite ? "the water height callback returned NaN or Inf"
                                             : nullptr;
                        })
                   ? 1
                   : 0;
    } catch (const std::exception& e) {
        return refuse(kCall, e.what());
    }
}

int plimsoll_batch_instance_step(plimsoll_batch* batch, size_t count,
                                 plimsoll_instance* const* instances, plimsoll_body_state* states,
                                 const plimsoll_water* water, const plimsoll_fluid* fluid,
                                 double time, double dt) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_batch_instance_step";
    try {
        if (!batch || (count > 0 && (!instances || !states)))
            return refuse(kCall, "batch, instances or states is NULL");
        if (count > static_cast<size_t>(INT32_MAX))
            return refuse(kCall, "more than 2^31 - 1 bodies");
        if (!checkWater(kCall, water) || !checkTime(kCall, time) || !checkFluid(kCall, fluid))
            return 0;
        if (!(dt > 0) || !std::isfinite(dt)) return refuse(kCall, "dt must be finite and > 0");
        for (std::size_t i = 0; i < count; ++i) {
            const std::string item = std::string(kCall) + ": body " + std::to_string(i);
            if (!instances[i]) return refuse(item.c_str(), "instance is NULL");
            if (!checkEvaluation(item.c_str(), &states[i].pose, &states[i].velocity, nullptr))
                return 0;
        }
        if (!distinct(kCall, count, instances,
                      "an instance appears twice (each steps once per call)"))
            return 0;
        return runBatch(*batch, kCall, count,
                        [&](std::size_t i) {
                            plimsoll_instance& instance = *instances[i];
                            const plimsoll_fluid f =
                                fluid ? *fluid : defaultFluid(instance.body.bundle());
                            return stepInstance(instance, states[i], instance.body.radiation(),
                                                water, f, time, dt, true);
                        })
                   ? 1
                   : 0;
    } catch (const std::exception& e) {
        return refuse(kCall, e.what());
    }
}

}  // extern "C"

plimsoll_simulation* plimsoll_simulation_create(const plimsoll_bundle* bundle) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_simulation_create";
    try {
        if (!bundle || !bundle->bundle) {
            refuse(kCall, "bundle is NULL");
            return nullptr;
        }
        std::string error;
        std::unique_ptr<Simulation> simulation = Simulation::create(*bundle->bundle, error);
        if (!simulation) {
            refuse(kCall, error);
            return nullptr;
        }
        lastError.clear();
        return new plimsoll_simulation{std::move(simulation),
                                       bundle->bundle->world().water.water()};
    } catch (const std::exception& e) {
        refuse(kCall, e.what());
        return nullptr;
    }
}

void plimsoll_simulation_destroy(plimsoll_simulation* simulation) {
    // Leaves the last error: freeing what a failed call returned comes before reading why.
    delete simulation;
}

int plimsoll_simulation_advance_frame(plimsoll_simulation* simulation,
                                      const plimsoll_water* water) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_simulation_advance_frame";
    try {
        if (!simulation) return refuse(kCall, "simulation is NULL");
        bool nonFinite = false;
        const Water caller = water ? toWater(water, &nonFinite) : Water{};
        std::string error;
        if (!simulation->simulation->advanceFrame(water ? caller : simulation->water, error))
            return refuse(kCall, error);
        if (nonFinite) return refuse(kCall, "the water callback returned NaN or Inf");
        lastError.clear();
        return 1;
    } catch (const std::exception& e) {
        return refuse(kCall, e.what());
    }
}

int plimsoll_simulation_state_query(const plimsoll_simulation* simulation,
                                    plimsoll_simulation_state* out) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_simulation_state_query";
    if (!simulation || !out) return refuse(kCall, "a required argument is NULL");
    const Simulation& s = *simulation->simulation;
    auto put = [](double* to, const Vec3& v) { to[0] = v.x, to[1] = v.y, to[2] = v.z; };
    out->time = s.time();
    out->frame_time = 0;
    put(out->center_of_mass, s.centerOfMass());
    const Quat& q = s.orientation();
    out->orientation[0] = q.w, out->orientation[1] = q.x, out->orientation[2] = q.y,
    out->orientation[3] = q.z;
    put(out->velocity, s.linearVelocity());
    put(out->angular_velocity, s.angularVelocity());
    out->submerged_volume = s.forces().submergedVolume;
    put(out->buoyant_force, s.forces().pressureForce);
    out->mass = s.mass().mass;
    put(out->local_center_of_mass, s.mass().centerOfMass);
    out->frame_time = s.frameTime();
    lastError.clear();
    return 1;
}

int plimsoll_simulation_save(const plimsoll_simulation* simulation, void* buffer, size_t capacity,
                             size_t* size) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_simulation_save";
    try {
        if (!simulation || !size) return refuse(kCall, "a required argument is NULL");
        return copySnapshot(kCall, simulation->simulation->save(), buffer, capacity, size);
    } catch (const std::exception& e) {
        return refuse(kCall, e.what());
    }
}

int plimsoll_simulation_restore(plimsoll_simulation* simulation, const void* bytes, size_t size) {
    lastError.clear();
    return restoreSnapshot("plimsoll_simulation_restore",
                           simulation ? simulation->simulation.get() : nullptr, bytes, size);
}

uint64_t plimsoll_simulation_state_hash(const plimsoll_simulation* simulation) {
    lastError.clear();
    return stateHashOf("plimsoll_simulation_state_hash", "simulation",
                       simulation ? simulation->simulation.get() : nullptr);
}

size_t plimsoll_bundle_level_count(const plimsoll_bundle* bundle) {
    lastError.clear();
    if (!bundle) {
        refuse("plimsoll_bundle_level_count", "bundle is NULL");
        return 0;
    }
    return bundle->bundle->levels().size();
}

int plimsoll_bundle_level_query(const plimsoll_bundle* bundle, size_t level,
                                plimsoll_level_info* out) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_bundle_level_query";
    if (!bundle || !out || out->struct_size < sizeof(plimsoll_level_info))
        return refuse(
            kCall, "bundle or out is NULL, or out->struct_size is not sizeof(plimsoll_level_info)");
    const std::vector<BundleLevel>& levels = bundle->bundle->levels();
    if (level >= levels.size())
        return refuse(kCall,
                      "level " + std::to_string(level) + " of " + std::to_string(levels.size()));
    const BundleLevel& l = levels[level];
    out->size = l.size;
    out->samples = l.samples;
    out->force_error = l.forceError;
    out->torque_error = l.torqueError;
    out->evaluation_us = l.evaluationUs;
    return 1;
}

plimsoll_level_policy plimsoll_level_policy_default(void) {
    lastError.clear();
    const LevelPolicy d;
    plimsoll_level_policy p{};
    p.struct_size = sizeof(plimsoll_level_policy);
    p.kind = PLIMSOLL_LEVEL_FINEST;
    p.near_distance = d.nearDistance;
    p.margin = d.margin;
    p.importance = d.importance;
    p.level = d.level;
    p.hold_frames = d.holdFrames;
    p.blend_frames = d.blendFrames;
    p.fewer_steps_when_coarser = d.fewerStepsWhenCoarser ? 1 : 0;
    return p;
}

int plimsoll_simulation_set_level_policy(plimsoll_simulation* simulation,
                                         const plimsoll_level_policy* policy) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_simulation_set_level_policy";
    // A caller built against a header before fewer_steps_when_coarser passes the size up to it.
    constexpr std::size_t kFirstSize = offsetof(plimsoll_level_policy, fewer_steps_when_coarser);
    if (!simulation || !policy || policy->struct_size < kFirstSize)
        return refuse(kCall,
                      "simulation or policy is NULL, or policy->struct_size is not "
                      "sizeof(plimsoll_level_policy)");
    LevelPolicy p;
    switch (policy->kind) {
        case PLIMSOLL_LEVEL_FINEST:
            p.kind = LevelPolicy::Kind::finest;
            break;
        case PLIMSOLL_LEVEL_DISTANCE:
            p.kind = LevelPolicy::Kind::distance;
            break;
        case PLIMSOLL_LEVEL_IMPORTANCE:
            p.kind = LevelPolicy::Kind::importance;
            break;
        case PLIMSOLL_LEVEL_FIXED:
            p.kind = LevelPolicy::Kind::fixed;
            break;
        default:
            return refuse(kCall,
                          "kind " + std::to_string(policy->kind) + " is not a PLIMSOLL_LEVEL_*");
    }
    p.pointOfInterest = {policy->point_of_interest[0], policy->point_of_interest[1],
                         policy->point_of_interest[2]};
    p.nearDistance = policy->near_distance;
    p.margin = policy->margin;
    p.importance = policy->importance;
    p.level = policy->level;
    p.holdFrames = policy->hold_frames;
    p.blendFrames = policy->blend_frames;
    if (policy->struct_size >= sizeof(plimsoll_level_policy))
        p.fewerStepsWhenCoarser = policy->fewer_steps_when_coarser != 0;
    std::string error;
    if (!simulation->simulation->setLevelPolicy(p, error)) return refuse(kCall, error);
    return 1;
}

size_t plimsoll_simulation_level(const plimsoll_simulation* simulation) {
    lastError.clear();
    if (!simulation) {
        refuse("plimsoll_simulation_level", "simulation is NULL");
        return 0;
    }
    return simulation->simulation->level();
}

extern "C" {

plimsoll_instance* plimsoll_instance_create(const plimsoll_bundle* bundle) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_instance_create";
    try {
        if (!bundle || !bundle->bundle) {
            refuse(kCall, "bundle is NULL");
            return nullptr;
        }
        return new plimsoll_instance{bundle, Body(*bundle->bundle)};
    } catch (const std::exception& e) {
        refuse(kCall, e.what());
        return nullptr;
    }
}

void plimsoll_instance_destroy(plimsoll_instance* instance) {
    // Leaves the last error: freeing what a failed call returned comes before reading why.
    delete instance;
}

const plimsoll_bundle* plimsoll_instance_bundle(const plimsoll_instance* instance) {
    lastError.clear();
    if (!instance) refuse("plimsoll_instance_bundle", "instance is NULL");
    return instance ? instance->bundle : nullptr;
}

uint64_t plimsoll_instance_memory_bytes(const plimsoll_instance* instance) {
    lastError.clear();
    if (!instance) {
        refuse("plimsoll_instance_memory_bytes", "instance is NULL");
        return 0;
    }
    return sizeof(plimsoll_instance) - sizeof(Body) + instance->body.memoryBytes();
}

int plimsoll_instance_node_water(const plimsoll_instance* instance, size_t node, double* water) {
    lastError.clear();
    return nodeWater("plimsoll_instance_node_water", instance, node, water);
}

int plimsoll_instance_set_node_water(plimsoll_instance* instance, size_t node, double water) {
    lastError.clear();
    return setNodeWater("plimsoll_instance_set_node_water", instance, node, water);
}

int plimsoll_instance_set_medium(plimsoll_instance* instance, double density, double viscosity,
                                 double gravity) {
    lastError.clear();
    return setMedium("plimsoll_instance_set_medium", instance, density, viscosity, gravity);
}

int plimsoll_instance_graph_inflow(const plimsoll_instance* instance, const plimsoll_pose* pose,
                                   const plimsoll_water* water, double time, double* inflow,
                                   double* outflow) {
    lastError.clear();
    return graphInflow("plimsoll_instance_graph_inflow", instance, pose, water, time, inflow,
                       outflow);
}

int plimsoll_instance_graph_step(plimsoll_instance* instance, const plimsoll_pose* pose,
                                 const plimsoll_water* water, double time, double dt) {
    lastError.clear();
    return graphStep("plimsoll_instance_graph_step", instance, pose, water, time, dt, false);
}

int plimsoll_instance_water_mass(const plimsoll_instance* instance, const double orientation[4],
                                 plimsoll_mass* out) {
    lastError.clear();
    return waterMassOf("plimsoll_instance_water_mass", instance, orientation, out);
}

int plimsoll_instance_water_load(const plimsoll_instance* instance, const plimsoll_pose* pose,
                                 const plimsoll_velocity* velocity, const plimsoll_water* water,
                                 const plimsoll_fluid* fluid, double time, double dt,
                                 plimsoll_load* out) {
    lastError.clear();
    return instanceWaterLoad("plimsoll_instance_water_load", instance, pose, velocity, water, fluid,
                             time, dt, out);
}

int plimsoll_instance_step(plimsoll_instance* instance, plimsoll_body_state* state,
                           const plimsoll_water* water, const plimsoll_fluid* fluid, double time,
                           double dt) {
    lastError.clear();
    return stepChecked("plimsoll_instance_step", instance, state,
                       instance ? instance->body.radiation() : nullptr, water, fluid, time, dt,
                       true);
}

int plimsoll_instance_radiation_begin(plimsoll_instance* instance, const plimsoll_pose* pose,
                                      double submerged_volume, plimsoll_radiation_load* out) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_instance_radiation_begin";
    if (!instance || !out) return refuse(kCall, "a required argument is NULL");
    if (!instance->body.radiation())
        return refuse(kCall, "the body was exported without radiation");
    return radiationBegin(kCall, *instance->body.radiation(), pose, submerged_volume, out);
}

int plimsoll_instance_radiation_advance(plimsoll_instance* instance, const plimsoll_pose* pose,
                                        const plimsoll_velocity* velocity, double dt) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_instance_radiation_advance";
    if (!instance || !velocity) return refuse(kCall, "a required argument is NULL");
    if (!instance->body.radiation())
        return refuse(kCall, "the body was exported without radiation");
    return radiationAdvance(kCall, *instance->body.radiation(), pose, velocity, dt);
}

double plimsoll_instance_radiation_energy(const plimsoll_instance* instance) {
    lastError.clear();
    if (!instance) refuse("plimsoll_instance_radiation_energy", "instance is NULL");
    return instance && instance->body.radiation() ? instance->body.radiation()->energy() : 0.0;
}

int plimsoll_instance_save(const plimsoll_instance* instance, void* buffer, size_t capacity,
                           size_t* size) {
    lastError.clear();
    constexpr const char* kCall = "plimsoll_instance_save";
    try {
        if (!instance || !size) return refuse(kCall, "a required argument is NULL");
        return copySnapshot(kCall, instance->body.save(), buffer, capacity, size);
    } catch (const std::exception& e) {
        return refuse(kCall, e.what());
    }
}

int plimsoll_instance_restore(plimsoll_instance* instance, const void* bytes, size_t size) {
    lastError.clear();
    return restoreSnapshot("plimsoll_instance_restore", instance ? &instance->body : nullptr, bytes,
                           size);
}

uint64_t plimsoll_instance_state_hash(const plimsoll_instance* instance) {
    lastError.clear();
    return stateHashOf("plimsoll_instance_state_hash", "instance",
                       instance ? &instance->body : nullptr);
}

int plimsoll_instance_asleep(const plimsoll_instance* instance) {
    lastError.clear();
    if (!instance) return refuse("plimsoll_instance_asleep", "instance is NULL");
    return instance->body.asleep() ? 1 : 0;
}

int plimsoll_instance_wake(plimsoll_instance* instance) {
    lastError.clear();
    if (!instance) return refuse("plimsoll_instance_wake", "instance is NULL");
    instance->body.wake();
    return 1;
}

}  // extern "C"
