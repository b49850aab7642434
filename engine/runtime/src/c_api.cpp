// The C API (plimsoll_runtime.h) over the C++ one: every entry point catches, so no exception
// crosses into C.
#include "plimsoll_runtime.h"

#include "plimsoll_runtime/runtime.hpp"

#include <cstring>
#include <memory>
#include <string>

struct plimsoll_bundle {
    std::unique_ptr<plimsoll_runtime::Bundle> bundle;
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

Water toWater(const plimsoll_water* w) {
    Water water;
    if (!w) return water;
    water.level = w->level;
    if (w->height) {
        const plimsoll_height_fn fn = w->height;
        void* user = w->user;
        water.height = [fn, user](double x, double z, double t) { return fn(user, x, z, t); };
    }
    if (w->velocity) {
        const plimsoll_water_velocity_fn fn = w->velocity;
        void* user = w->user;
        water.velocity = [fn, user](const Vec3& p, double t) {
            const double point[3] = {p.x, p.y, p.z};
            double v[3] = {0, 0, 0};
            fn(user, point, t, v);
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

bool hasGraph(const plimsoll_bundle* b) { return b && b->bundle && b->bundle->graph(); }

}  // namespace

extern "C" {

const char* plimsoll_runtime_last_error(void) { return lastError.c_str(); }

const char* plimsoll_runtime_schema_version(void) {
    static const std::string version = std::to_string(kSchemaMajor) + "." + std::to_string(kSchemaMinor);
    return version.c_str();
}

plimsoll_bundle* plimsoll_bundle_load(const char* folder, int verify_checksums) {
    try {
        if (!folder) {
            setError("plimsoll_bundle_load: folder is NULL");
            return nullptr;
        }
        std::string error;
        LoadOptions options;
        options.verifyChecksums = verify_checksums != 0;
        auto bundle = loadBundle(folder, error, options);
        if (!bundle) {
            setError(error);
            return nullptr;
        }
        auto* handle = new plimsoll_bundle;
        handle->bundle = std::move(bundle);
        lastError.clear();
        return handle;
    } catch (const std::exception& e) {
        setError(std::string("plimsoll_bundle_load: ") + e.what());
        return nullptr;
    }
}

void plimsoll_bundle_free(plimsoll_bundle* bundle) { delete bundle; }

const char* plimsoll_bundle_body(const plimsoll_bundle* bundle) {
    return bundle ? bundle->bundle->body().c_str() : "";
}

size_t plimsoll_bundle_sample_count(const plimsoll_bundle* bundle) {
    return bundle ? bundle->bundle->samples().size() : 0;
}

plimsoll_mass plimsoll_bundle_mass(const plimsoll_bundle* bundle) {
    return bundle ? toC(bundle->bundle->mass()) : plimsoll_mass{};
}

plimsoll_fluid plimsoll_bundle_default_fluid(const plimsoll_bundle* bundle) {
    plimsoll_fluid out{1000.0, 9.81, 1.0, 0.0};
    if (bundle) {
        out.drag_coefficient = bundle->bundle->fluid().dragCoefficient;
        out.friction_coefficient = bundle->bundle->fluid().frictionCoefficient;
    }
    return out;
}

void plimsoll_bundle_damping(const plimsoll_bundle* bundle, double* linear, double* angular) {
    if (linear) *linear = bundle ? bundle->bundle->linearDamping() : 0.0;
    if (angular) *angular = bundle ? bundle->bundle->angularDamping() : 0.0;
}

int plimsoll_bundle_evaluate(const plimsoll_bundle* bundle, const plimsoll_pose* pose,
                             const plimsoll_velocity* velocity, const plimsoll_water* water,
                             const plimsoll_fluid* fluid, double time, plimsoll_forces* out) {
    try {
        if (!bundle || !pose || !fluid || !out) {
            setError("plimsoll_bundle_evaluate: a required argument is NULL");
            return 0;
        }
        Velocity v;
        if (velocity) {
            v.linear = {velocity->linear[0], velocity->linear[1], velocity->linear[2]};
            v.angular = {velocity->angular[0], velocity->angular[1], velocity->angular[2]};
        }
        Fluid f;
        f.density = fluid->density;
        f.gravity = fluid->gravity;
        f.dragCoefficient = fluid->drag_coefficient;
        f.frictionCoefficient = fluid->friction_coefficient;
        const Forces r = bundle->bundle->evaluate(toPose(*pose), v, toWater(water), f, time);
        out->submerged_volume = r.submergedVolume;
        copy(r.centerOfBuoyancy, out->center_of_buoyancy);
        copy(r.force, out->force);
        copy(r.torque, out->torque);
        copy(r.pressureForce, out->pressure_force);
        copy(r.pressureTorque, out->pressure_torque);
        copy(r.dragForce, out->drag_force);
        copy(r.dragTorque, out->drag_torque);
        out->wetted_area = r.wettedArea;
        out->submerged_samples = r.submergedSamples;
        return 1;
    } catch (const std::exception& e) {
        setError(std::string("plimsoll_bundle_evaluate: ") + e.what());
        return 0;
    }
}

size_t plimsoll_graph_node_count(const plimsoll_bundle* bundle) {
    return hasGraph(bundle) ? bundle->bundle->graph()->nodes().size() : 0;
}

double plimsoll_graph_node_water(const plimsoll_bundle* bundle, size_t node) {
    if (!hasGraph(bundle) || node >= plimsoll_graph_node_count(bundle)) return 0.0;
    return bundle->bundle->graph()->nodes()[node].water;
}

double plimsoll_graph_node_capacity(const plimsoll_bundle* bundle, size_t node) {
    if (!hasGraph(bundle) || node >= plimsoll_graph_node_count(bundle)) return 0.0;
    return bundle->bundle->graph()->nodes()[node].capacity;
}

int plimsoll_graph_set_node_water(plimsoll_bundle* bundle, size_t node, double water) {
    if (!hasGraph(bundle) || node >= plimsoll_graph_node_count(bundle)) {
        setError("plimsoll_graph_set_node_water: no such node");
        return 0;
    }
    bundle->bundle->graph()->setWater(node, water);
    return 1;
}

int plimsoll_graph_set_medium(plimsoll_bundle* bundle, double density, double viscosity,
                              double gravity) {
    if (!hasGraph(bundle)) {
        setError("plimsoll_graph_set_medium: the body has no water graph");
        return 0;
    }
    if (!(density > 0) || !(viscosity > 0) || !(gravity >= 0)) {
        setError("plimsoll_graph_set_medium: density and viscosity must be > 0, gravity >= 0");
        return 0;
    }
    GraphSettings& s = bundle->bundle->graph()->settings();
    s.density = density;
    s.viscosity = viscosity;
    s.gravity = gravity;
    return 1;
}

int plimsoll_graph_inflow(const plimsoll_bundle* bundle, const plimsoll_pose* pose,
                          const plimsoll_water* water, double time, double* inflow,
                          double* outflow) {
    try {
        if (!hasGraph(bundle) || !pose) {
            setError("plimsoll_graph_inflow: no water graph or no pose");
            return 0;
        }
        const NodeInflow r = bundle->bundle->graph()->inflow(toPose(*pose), toWater(water), time);
        for (std::size_t i = 0; i < r.inflow.size(); ++i) {
            if (inflow) inflow[i] = r.inflow[i];
            if (outflow) outflow[i] = r.outflow[i];
        }
        return 1;
    } catch (const std::exception& e) {
        setError(std::string("plimsoll_graph_inflow: ") + e.what());
        return 0;
    }
}

int plimsoll_graph_step(plimsoll_bundle* bundle, const plimsoll_pose* pose,
                        const plimsoll_water* water, double time, double dt) {
    try {
        if (!hasGraph(bundle) || !pose || !(dt >= 0)) {
            setError("plimsoll_graph_step: no water graph, no pose or dt < 0");
            return -1;
        }
        return bundle->bundle->graph()->step(toPose(*pose), toWater(water), time, dt) ? 1 : 0;
    } catch (const std::exception& e) {
        setError(std::string("plimsoll_graph_step: ") + e.what());
        return -1;
    }
}

plimsoll_mass plimsoll_graph_water_mass(const plimsoll_bundle* bundle, const double orientation[4]) {
    if (!hasGraph(bundle) || !orientation) return plimsoll_mass{};
    try {
        return toC(bundle->bundle->graph()->waterMass(
            {orientation[0], orientation[1], orientation[2], orientation[3]}));
    } catch (const std::exception&) {
        return plimsoll_mass{};
    }
}

}  // extern "C"
