// plimsoll.Bundle, plimsoll.Instance and plimsoll.Simulation: the runtime library's asset and
// instance API through its C ABI (plimsoll_runtime.h, docs/c-abi.md), the API a game ships
// against, so that a script sees exactly what a game sees. Poses are (position, quaternion
// w, x, y, z); a failed call raises plimsoll.Error with kind "runtime" and the runtime's
// message.
#include "module.h"

#include "plimsoll_runtime.h"

#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace py = pybind11;

namespace plimsoll::python {

namespace {

[[noreturn]] void raiseRuntime() { raise(plimsoll_runtime_last_error(), "runtime"); }

void check(int ok) {
    if (!ok) raiseRuntime();
}

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;

py::array_t<double> array3(const double v[3]) {
    py::array_t<double> out(3);
    std::copy(v, v + 3, out.mutable_data());
    return out;
}

py::dict massDict(const plimsoll_mass& m) {
    py::array_t<double> inertia({3, 3});
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) inertia.mutable_at(r, c) = m.inertia[r][c];
    py::dict out;
    out["mass"] = m.mass;
    out["volume"] = m.volume;
    out["center_of_mass"] = array3(m.center_of_mass);
    out["inertia"] = inertia;
    return out;
}

py::dict forcesDict(const plimsoll_forces& f) {
    py::dict out;
    out["submerged_volume"] = f.submerged_volume;
    out["center_of_buoyancy"] = array3(f.center_of_buoyancy);
    out["force"] = array3(f.force);
    out["torque"] = array3(f.torque);
    out["pressure_force"] = array3(f.pressure_force);
    out["pressure_torque"] = array3(f.pressure_torque);
    out["drag_force"] = array3(f.drag_force);
    out["drag_torque"] = array3(f.drag_torque);
    out["wetted_area"] = f.wetted_area;
    out["submerged_samples"] = f.submerged_samples;
    return out;
}

plimsoll_pose poseOf(const Vec3& position, const Quat& orientation) {
    plimsoll_pose pose;
    std::copy(position.begin(), position.end(), pose.position);
    std::copy(orientation.begin(), orientation.end(), pose.orientation);
    return pose;
}

plimsoll_velocity velocityOf(const Vec3& linear, const Vec3& angular) {
    plimsoll_velocity v;
    std::copy(linear.begin(), linear.end(), v.linear);
    std::copy(angular.begin(), angular.end(), v.angular);
    return v;
}

/// Flat water at `level` (the runtime's callbacks are for a game's own water model).
plimsoll_water flatWater(double level) {
    plimsoll_water water{};
    water.level = level;
    return water;
}

plimsoll_fluid fluidOf(const plimsoll_bundle* bundle, const std::optional<py::dict>& fluid) {
    plimsoll_fluid f = plimsoll_bundle_default_fluid(bundle);
    if (fluid) {
        for (auto [key, value] : *fluid) {
            const std::string name = py::str(key);
            const double v = value.cast<double>();
            if (name == "density")
                f.density = v;
            else if (name == "gravity")
                f.gravity = v;
            else if (name == "drag_coefficient")
                f.drag_coefficient = v;
            else if (name == "friction_coefficient")
                f.friction_coefficient = v;
            else
                raise({"fluid: unknown key '" + name +
                           "' (density, gravity, drag_coefficient, friction_coefficient)",
                       ErrorKind::invalidArgument});
        }
    }
    return f;
}

py::bytes snapshot(const std::function<int(void*, std::size_t, std::size_t*)>& save) {
    std::size_t size = 0;
    save(nullptr, 0, &size);
    std::string bytes(size, '\0');
    check(save(bytes.data(), bytes.size(), &size));
    return py::bytes(bytes);
}

struct Bundle {
    std::shared_ptr<plimsoll_bundle> handle;
    const plimsoll_bundle* get() const { return handle.get(); }
};

Bundle loadBundle(const std::string& folder, bool verify) {
    plimsoll_bundle* bundle = plimsoll_bundle_load(folder.c_str(), verify ? 1 : 0);
    if (!bundle) raiseRuntime();
    return {std::shared_ptr<plimsoll_bundle>(bundle, plimsoll_bundle_destroy)};
}

/// An instance keeps its bundle alive (the C API needs the bundle to outlive it).
struct Instance {
    Bundle bundle;
    std::shared_ptr<plimsoll_instance> handle;
    plimsoll_instance* get() const { return handle.get(); }
};

struct Simulation {
    Bundle bundle;
    std::shared_ptr<plimsoll_simulation> handle;
    plimsoll_simulation* get() const { return handle.get(); }
};

py::dict simulationState(const Simulation& s) {
    plimsoll_simulation_state state;
    check(plimsoll_simulation_state_query(s.get(), &state));
    py::dict out;
    out["time"] = state.time;
    out["frame_time"] = state.frame_time;
    out["center_of_mass"] = array3(state.center_of_mass);
    py::array_t<double> q(4);
    std::copy(state.orientation, state.orientation + 4, q.mutable_data());
    out["orientation"] = q;
    out["velocity"] = array3(state.velocity);
    out["angular_velocity"] = array3(state.angular_velocity);
    out["submerged_volume"] = state.submerged_volume;
    out["buoyant_force"] = array3(state.buoyant_force);
    out["mass"] = state.mass;
    out["local_center_of_mass"] = array3(state.local_center_of_mass);
    return out;
}

/// `frames` frames as rows of the `simulate --out` columns without the body's name.
py::array_t<double> runFrames(Simulation& s, long frames) {
    if (frames < 0) raise({"frames: expected a count >= 0", ErrorKind::invalidArgument});
    std::vector<double> rows;
    rows.reserve(static_cast<std::size_t>(frames) * 22);
    bool failed = false;
    {
        py::gil_scoped_release release;
        plimsoll_simulation_state st;
        for (long f = 0; f < frames && !failed; ++f) {
            if (!plimsoll_simulation_advance_frame(s.get(), nullptr) ||
                !plimsoll_simulation_state_query(s.get(), &st)) {
                failed = true;
                break;
            }
            const double row[22] = {st.time,
                                    st.center_of_mass[0],
                                    st.center_of_mass[1],
                                    st.center_of_mass[2],
                                    st.orientation[0],
                                    st.orientation[1],
                                    st.orientation[2],
                                    st.orientation[3],
                                    st.velocity[0],
                                    st.velocity[1],
                                    st.velocity[2],
                                    st.angular_velocity[0],
                                    st.angular_velocity[1],
                                    st.angular_velocity[2],
                                    st.submerged_volume,
                                    st.buoyant_force[0],
                                    st.buoyant_force[1],
                                    st.buoyant_force[2],
                                    st.mass,
                                    st.local_center_of_mass[0],
                                    st.local_center_of_mass[1],
                                    st.local_center_of_mass[2]};
            rows.insert(rows.end(), row, row + 22);
        }
    }
    if (failed) raiseRuntime();
    py::array_t<double> out({static_cast<py::ssize_t>(rows.size() / 22), py::ssize_t{22}});
    std::copy(rows.begin(), rows.end(), out.mutable_data());
    return out;
}

}  // namespace

void bindRuntime(py::module_& m) {
    using namespace pybind11::literals;

    m.def(
        "runtime_version",
        [] {
            int major = 0, minor = 0, patch = 0;
            plimsoll_runtime_version(&major, &minor, &patch);
            return py::make_tuple(major, minor, patch);
        },
        "The runtime library's version (major, minor, patch).");

    py::class_<Bundle>(m, "Bundle",
                       "A loaded runtime bundle (the asset): immutable, shared by its instances.")
        .def(py::init(&loadBundle), "folder"_a, "verify"_a = true,
             "Loads the bundle in `folder` (as `plimsoll export` writes it); verify checks every "
             "file's SHA-256 against the manifest.")
        .def_property_readonly(
            "body", [](const Bundle& b) { return std::string(plimsoll_bundle_body(b.get())); })
        .def_property_readonly(
            "sample_count", [](const Bundle& b) { return plimsoll_bundle_sample_count(b.get()); })
        .def_property_readonly(
            "mass", [](const Bundle& b) { return massDict(plimsoll_bundle_mass(b.get())); })
        .def_property_readonly("default_fluid",
                               [](const Bundle& b) {
                                   const plimsoll_fluid f = plimsoll_bundle_default_fluid(b.get());
                                   return py::dict(
                                       "density"_a = f.density, "gravity"_a = f.gravity,
                                       "drag_coefficient"_a = f.drag_coefficient,
                                       "friction_coefficient"_a = f.friction_coefficient);
                               })
        .def_property_readonly("node_count",
                               [](const Bundle& b) { return plimsoll_graph_node_count(b.get()); })
        .def(
            "node_capacity",
            [](const Bundle& b, std::size_t node) {
                if (node >= plimsoll_graph_node_count(b.get()))
                    raise({"node " + std::to_string(node) + ": out of range",
                           ErrorKind::invalidArgument});
                return plimsoll_graph_node_capacity(b.get(), node);
            },
            "node"_a)
        .def(
            "evaluate",
            [](const Bundle& b, const Vec3& position, const Quat& orientation, double waterLevel,
               const Vec3& velocity, const Vec3& angularVelocity, double time,
               const std::optional<py::dict>& fluid) {
                const plimsoll_pose pose = poseOf(position, orientation);
                const plimsoll_velocity v = velocityOf(velocity, angularVelocity);
                const plimsoll_water water = flatWater(waterLevel);
                const plimsoll_fluid f = fluidOf(b.get(), fluid);
                plimsoll_forces out;
                check(plimsoll_bundle_evaluate(b.get(), &pose, &v, &water, &f, time, &out));
                return forcesDict(out);
            },
            "position"_a, "orientation"_a, "water_level"_a = 0.0, "velocity"_a = Vec3{0, 0, 0},
            "angular_velocity"_a = Vec3{0, 0, 0}, "time"_a = 0.0, "fluid"_a = py::none(),
            "Buoyancy, pressure and drag at a pose (quaternion w, x, y, z) on flat water.");

    py::class_<Instance>(m, "Instance",
                         "One body of a bundle: its water, radiation memory and step state.")
        .def(py::init([](const Bundle& bundle) {
                 plimsoll_instance* instance = plimsoll_instance_create(bundle.get());
                 if (!instance) raiseRuntime();
                 return Instance{bundle, std::shared_ptr<plimsoll_instance>(
                                             instance, plimsoll_instance_destroy)};
             }),
             "bundle"_a)
        .def_property_readonly("bundle", [](const Instance& i) { return i.bundle; })
        .def_property_readonly(
            "memory_bytes",
            [](const Instance& i) { return plimsoll_instance_memory_bytes(i.get()); })
        .def(
            "node_water",
            [](const Instance& i, std::size_t node) {
                double water = 0;
                check(plimsoll_instance_node_water(i.get(), node, &water));
                return water;
            },
            "node"_a, "Water in a node of the water graph, m^3.")
        .def(
            "set_node_water",
            [](Instance& i, std::size_t node, double water) {
                check(plimsoll_instance_set_node_water(i.get(), node, water));
            },
            "node"_a, "water"_a)
        .def(
            "water_mass",
            [](const Instance& i, const Quat& orientation) {
                plimsoll_mass out;
                check(plimsoll_instance_water_mass(i.get(), orientation.data(), &out));
                return massDict(out);
            },
            "orientation"_a)
        .def(
            "water_load",
            [](const Instance& i, const Vec3& position, const Quat& orientation,
               const Vec3& velocity, const Vec3& angularVelocity, double waterLevel, double time,
               double dt, const std::optional<py::dict>& fluid) {
                const plimsoll_pose pose = poseOf(position, orientation);
                const plimsoll_velocity v = velocityOf(velocity, angularVelocity);
                const plimsoll_water water = flatWater(waterLevel);
                const plimsoll_fluid f = fluidOf(i.bundle.get(), fluid);
                plimsoll_load out;
                check(plimsoll_instance_water_load(i.get(), &pose, &v, &water, &f, time, dt, &out));
                py::dict d;
                d["force"] = array3(out.force);
                d["torque"] = array3(out.torque);
                d["water_mass"] = out.water_mass;
                d["forces"] = forcesDict(out.forces);
                return d;
            },
            "position"_a, "orientation"_a, "velocity"_a = Vec3{0, 0, 0},
            "angular_velocity"_a = Vec3{0, 0, 0}, "water_level"_a = 0.0, "time"_a = 0.0,
            "dt"_a = 1.0 / 60.0, "fluid"_a = py::none(),
            "What a physics engine applies to the body: force and torque at the centre of mass.")
        .def(
            "step",
            [](Instance& i, const Vec3& position, const Quat& orientation, const Vec3& velocity,
               const Vec3& angularVelocity, double waterLevel, double time, double dt,
               const std::optional<py::dict>& fluid) {
                plimsoll_body_state state{poseOf(position, orientation),
                                          velocityOf(velocity, angularVelocity)};
                const plimsoll_water water = flatWater(waterLevel);
                const plimsoll_fluid f = fluidOf(i.bundle.get(), fluid);
                check(plimsoll_instance_step(i.get(), &state, &water, &f, time, dt));
                return py::make_tuple(
                    Vec3{state.pose.position[0], state.pose.position[1], state.pose.position[2]},
                    Quat{state.pose.orientation[0], state.pose.orientation[1],
                         state.pose.orientation[2], state.pose.orientation[3]},
                    Vec3{state.velocity.linear[0], state.velocity.linear[1],
                         state.velocity.linear[2]},
                    Vec3{state.velocity.angular[0], state.velocity.angular[1],
                         state.velocity.angular[2]});
            },
            "position"_a, "orientation"_a, "velocity"_a = Vec3{0, 0, 0},
            "angular_velocity"_a = Vec3{0, 0, 0}, "water_level"_a = 0.0, "time"_a = 0.0,
            "dt"_a = 1.0 / 240.0, "fluid"_a = py::none(),
            "One semi-implicit Euler step of the body on its own (plimsoll_instance_step) on flat "
            "water; returns (position, orientation, velocity, angular_velocity).")
        .def(
            "save",
            [](const Instance& i) {
                return snapshot([&](void* buffer, std::size_t capacity, std::size_t* size) {
                    return plimsoll_instance_save(i.get(), buffer, capacity, size);
                });
            },
            "A snapshot of the instance (bytes): restore() continues bit for bit.")
        .def(
            "restore",
            [](Instance& i, const py::bytes& bytes) {
                const std::string data = bytes;
                check(plimsoll_instance_restore(i.get(), data.data(), data.size()));
            },
            "bytes"_a)
        .def_property_readonly(
            "state_hash", [](const Instance& i) { return plimsoll_instance_state_hash(i.get()); })
        .def_property_readonly(
            "asleep", [](const Instance& i) { return plimsoll_instance_asleep(i.get()) == 1; })
        .def("wake", [](Instance& i) { check(plimsoll_instance_wake(i.get())); });

    py::class_<Simulation>(
        m, "Simulation",
        "The project's own run replayed from a bundle, as `plimsoll simulate` steps it.")
        .def(py::init([](const Bundle& bundle) {
                 plimsoll_simulation* simulation = plimsoll_simulation_create(bundle.get());
                 if (!simulation) raiseRuntime();
                 return Simulation{bundle, std::shared_ptr<plimsoll_simulation>(
                                               simulation, plimsoll_simulation_destroy)};
             }),
             "bundle"_a)
        .def(
            "advance_frame",
            [](Simulation& s) { check(plimsoll_simulation_advance_frame(s.get(), nullptr)); },
            "One frame of the project's time step on the bundle's own water.")
        .def(
            "run",
            [](Simulation& s, double seconds) {
                if (!(seconds >= 0))
                    raise({"seconds: expected a number >= 0", ErrorKind::invalidArgument});
                plimsoll_simulation_state state;
                check(plimsoll_simulation_state_query(s.get(), &state));
                // As plimsoll simulate and float_body count frames: ceil(seconds / step), less a
                // hair.
                return runFrames(s,
                                 static_cast<long>(std::ceil(seconds / state.frame_time - 1e-9)));
            },
            "seconds"_a,
            "Frames for `seconds`: an array of rows with the columns of `simulate --out` (without "
            "the body's name), as float_body --csv writes them.")
        .def_property_readonly("state", &simulationState)
        .def("save",
             [](const Simulation& s) {
                 return snapshot([&](void* buffer, std::size_t capacity, std::size_t* size) {
                     return plimsoll_simulation_save(s.get(), buffer, capacity, size);
                 });
             })
        .def(
            "restore",
            [](Simulation& s, const py::bytes& bytes) {
                const std::string data = bytes;
                check(plimsoll_simulation_restore(s.get(), data.data(), data.size()));
            },
            "bytes"_a)
        .def_property_readonly("state_hash", [](const Simulation& s) {
            return plimsoll_simulation_state_hash(s.get());
        });
}

}  // namespace plimsoll::python
