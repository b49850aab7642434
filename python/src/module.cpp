// The Python module `plimsoll`: the engine's main jobs (validate, bake, mass properties,
// buoyancy at a pose, hydrostatics, simulate, export) and the runtime's asset and instance
// API (runtime.cpp), with NumPy arrays. The jobs are the command line's own (editor/cli/jobs.h):
// a dictionary here holds what the command's --json prints, and a failure raises
// plimsoll.Error with the message and kind the command line reports (docs/python.md).
#include "module.h"

#include "cli/jobs.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/surface/atlas.h"

#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>

namespace py = pybind11;

namespace plimsoll::python {

namespace {

/// plimsoll.Error (kept for the life of the process, as the module is).
PyObject* errorType = nullptr;

/// Python objects from JSON: objects become dicts, arrays lists, numbers floats or ints.
py::object fromJson(const nlohmann::json& j) {
    switch (j.type()) {
        case nlohmann::json::value_t::null:
            return py::none();
        case nlohmann::json::value_t::boolean:
            return py::bool_(j.get<bool>());
        case nlohmann::json::value_t::number_integer:
            return py::int_(j.get<std::int64_t>());
        case nlohmann::json::value_t::number_unsigned:
            return py::int_(j.get<std::uint64_t>());
        case nlohmann::json::value_t::number_float:
            return py::float_(j.get<double>());
        case nlohmann::json::value_t::string:
            return py::str(j.get<std::string>());
        case nlohmann::json::value_t::array: {
            py::list list;
            for (const nlohmann::json& item : j) list.append(fromJson(item));
            return list;
        }
        case nlohmann::json::value_t::object: {
            py::dict dict;
            for (const auto& [key, value] : j.items()) dict[py::str(key)] = fromJson(value);
            return dict;
        }
        default:
            return py::none();
    }
}

/// The same dictionary with the vectors and matrices named in `arrays` as float64 arrays.
py::dict withArrays(const nlohmann::json& j, std::initializer_list<const char*> arrays) {
    py::dict out = fromJson(j);
    for (const char* key : arrays) {
        if (out.contains(key) && !out[key].is_none())
            out[key] = py::array_t<double>(
                py::module_::import("numpy").attr("asarray")(out[key], "float64"));
    }
    return out;
}

/// Notes go to the caller's callable (`notes=print`, say); without one they are dropped. No
/// progress: a module call is not a terminal.
cli::Reporter reporterFor(const py::object& notes) {
    cli::Reporter reporter;
    if (!notes.is_none()) {
        reporter.notes = [notes](const std::string& text) {
            py::gil_scoped_acquire gil;
            notes(text);
        };
    }
    return reporter;
}

/// Runs a job with the GIL released (it may take seconds) and returns its value.
template <class F>
auto withoutGil(F&& job) {
    py::gil_scoped_release release;
    return job();
}

cli::BakeOptions bakeOptions(int size, const Unit& unit, const std::string& atlas,
                             std::optional<double> maxTexelStretch) {
    if (size < kMinTextureSize || size > kMaxTextureSize)
        raise({"size " + std::to_string(size) + ": expected " + std::to_string(kMinTextureSize) +
                   " to " + std::to_string(kMaxTextureSize) + " texels per side",
               ErrorKind::invalidArgument});
    cli::BakeOptions options;
    options.size = size;
    options.unitScale = unitScale(unit);
    if (maxTexelStretch) options.maxTexelStretch = *maxTexelStretch;
    std::optional<AtlasMode> mode = parseAtlasMode(atlas);
    if (!mode)
        raise(
            {"atlas '" + atlas + "': expected mesh, auto or generate", ErrorKind::invalidArgument});
    options.atlas = *mode;
    return options;
}

Eigen::Vector3d vector3(const std::optional<std::array<double, 3>>& v) {
    if (!v) return Eigen::Vector3d::Zero();
    const Eigen::Vector3d out((*v)[0], (*v)[1], (*v)[2]);
    if (!out.allFinite())
        raise({"a vector with a NaN or Inf component", ErrorKind::invalidArgument});
    return out;
}

py::dict validate(const std::string& mesh, const Unit& unit) {
    // Checked with the GIL held: a bad unit raises a Python exception.
    const double scale = unitScale(unit);
    Result<cli::Validation> v = withoutGil([&] { return cli::validateJob(mesh, scale); });
    return fromJson(value(std::move(v)).json);
}

py::dict bake(const std::string& mesh, int size, const Unit& unit, const std::string& atlas,
              std::optional<double> maxTexelStretch, const py::object& notes) {
    const cli::BakeOptions options = bakeOptions(size, unit, atlas, maxTexelStretch);
    const cli::Reporter reporter = reporterFor(notes);
    struct Baked {
        cli::BakeableMesh mesh;
        SurfaceTextures textures;
    };
    Result<Baked> baked = withoutGil([&]() -> Result<Baked> {
        Result<cli::BakeableMesh> m = cli::bakeableMeshOf(mesh, options, reporter);
        if (!m) return m.error();
        Result<SurfaceTextures> t = cli::bakeTextures(m->mesh, options, reporter);
        if (!t) return t.error();
        return Baked{std::move(*m), std::move(*t)};
    });
    const Baked b = value(std::move(baked));
    const cli::BakeableMesh& m = b.mesh;
    const SurfaceTextures& t = b.textures;
    const py::ssize_t n = static_cast<py::ssize_t>(t.coveredCount());
    py::array_t<std::uint32_t> texel(n);
    py::array_t<double> position({n, py::ssize_t{3}}), areaVector({n, py::ssize_t{3}}), area(n),
        coverage(n);
    auto ti = texel.mutable_unchecked<1>();
    auto p = position.mutable_unchecked<2>();
    auto a = areaVector.mutable_unchecked<2>();
    auto s = area.mutable_unchecked<1>();
    auto c = coverage.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) {
        ti(i) = t.texelIndex[i];
        for (int k = 0; k < 3; ++k) {
            p(i, k) = t.position[i][k];
            a(i, k) = t.areaVector[i][k];
        }
        s(i) = t.area[i];
        c(i) = t.coverage[i];
    }
    py::dict out;
    out["mesh"] = mesh;
    out["size"] = t.size;
    out["atlas"] = m.generatedAtlas ? "generated" : "mesh";
    out["repairs"] = fromJson(cli::repairsJson(m.report.repairs));
    out["unit_scale"] = m.report.facts.unitScale;
    out["texel_index"] = texel;
    out["position"] = position;
    out["area_vector"] = areaVector;
    out["area"] = area;
    out["coverage"] = coverage;
    out["covered_texels"] = t.distinctTexelCount();
    out["uv_coverage"] = t.uvCoverage();
    out["surface_area"] = t.surfaceArea();
    out["closure_error"] = t.closureError();
    return out;
}

py::dict massprops(const std::string& mesh, int size, bool exact, std::optional<double> density,
                   double shellDensity, const std::string& shellDensityMap, const Unit& unit,
                   const std::string& atlas, std::optional<double> maxTexelStretch,
                   const std::string& body, const py::object& notes) {
    cli::MassPropsJob job;
    job.mesh = mesh;
    job.body = body;
    job.bake = bakeOptions(size, unit, atlas, maxTexelStretch);
    job.exact = exact;
    job.densityGiven = density.has_value();
    job.density = density.value_or(1000.0);
    job.shellDensity = shellDensity;
    job.shellDensityMap = shellDensityMap;
    if (!std::isfinite(job.density) || job.density < 0 || !std::isfinite(shellDensity) ||
        shellDensity < 0)
        raise({"density and shell_density: expected finite numbers >= 0",
               ErrorKind::invalidArgument});
    if (exact && !shellDensityMap.empty())
        raise({"shell_density_map: the exact method has no texels to paint",
               ErrorKind::invalidArgument});
    const cli::Reporter reporter = reporterFor(notes);
    Result<cli::MassPropsOutcome> outcome =
        withoutGil([&] { return cli::massPropsJob(job, reporter); });
    return withArrays(value(std::move(outcome)).json, {"center_of_mass", "inertia"});
}

py::dict buoyancy(const std::string& mesh, std::array<double, 3> position,
                  std::array<double, 3> rotationDeg, double waterLevel,
                  std::optional<std::array<double, 3>> velocity,
                  std::optional<std::array<double, 3>> angularVelocity, int size, bool exact,
                  const std::string& device, double fluidDensity, double dragCoefficient,
                  double frictionCoefficient, bool compareExact, const Unit& unit,
                  const std::string& atlas, const py::object& notes) {
    cli::BuoyancyJob job;
    job.mesh = mesh;
    job.bake = bakeOptions(size, unit, atlas, std::nullopt);
    job.exact = exact;
    job.device = device;
    job.waterLevel = waterLevel;
    job.position = vector3(position);
    job.rotationDegrees = vector3(rotationDeg);
    job.motion.linear = vector3(velocity);
    job.motion.angular = vector3(angularVelocity);
    job.fluid.density = fluidDensity;
    job.fluid.dragCoefficient = dragCoefficient;
    job.fluid.frictionCoefficient = frictionCoefficient;
    job.compareExact = compareExact;
    if (!std::isfinite(waterLevel) || !(fluidDensity > 0) || !std::isfinite(fluidDensity) ||
        !(dragCoefficient >= 0) || !(frictionCoefficient >= 0))
        raise(
            {"water_level, fluid_density, drag_coefficient, friction_coefficient: expected finite "
             "numbers (a density > 0, coefficients >= 0)",
             ErrorKind::invalidArgument});
    const cli::Reporter reporter = reporterFor(notes);
    Result<cli::BuoyancyOutcome> outcome =
        withoutGil([&] { return cli::buoyancyJob(job, reporter); });
    return withArrays(value(std::move(outcome)).json,
                      {"center_of_buoyancy", "force", "torque", "pressure_force", "pressure_torque",
                       "drag_force", "drag_torque"});
}

py::dict hydrostatics(const std::string& project, const std::string& body, bool exact,
                      double stepDeg, const py::object& notes) {
    if (!(stepDeg >= 0.01 && stepDeg <= 90.0))
        raise({"step_deg: expected 0.01 to 90 degrees", ErrorKind::invalidArgument});
    const cli::HydrostaticsJob job{project, body, exact, stepDeg};
    const cli::Reporter reporter = reporterFor(notes);
    Result<cli::HydrostaticsStudy> study =
        withoutGil([&] { return cli::hydrostaticsJob(job, reporter); });
    const nlohmann::json json = value(std::move(study)).json();
    py::dict out = withArrays(json, {"center_of_mass", "center_of_flotation", "gz"});
    if (json.contains("exact"))
        out["exact"] = withArrays(json["exact"], {"center_of_flotation", "gz"});
    return out;
}

/// The trajectory as `simulate --out` writes it: one row per frame and body.
py::dict simulate(const std::optional<std::string>& project, std::optional<double> seconds,
                  const std::optional<std::string>& mesh, double density, int size,
                  double fluidDensity, double waterLevel,
                  std::optional<std::array<double, 3>> position,
                  std::optional<std::array<double, 3>> rotationDeg, bool noRadiation,
                  const Unit& unit, const std::string& device,
                  const std::optional<std::string>& integrator, const py::object& notes) {
    if (project.has_value() == mesh.has_value())
        raise({"simulate: give a project or mesh=, not both", ErrorKind::invalidArgument});
    if (seconds && !(std::isfinite(*seconds) && *seconds >= 0))
        raise({"seconds: expected a finite number >= 0", ErrorKind::invalidArgument});
    cli::SimulateJob job;
    job.project = project.value_or("");
    job.mesh = mesh.value_or("");
    job.seconds = seconds;
    job.device = device;
    job.unitScale = unitScale(unit);
    job.density = density;
    job.size = size;
    job.fluidDensity = fluidDensity;
    job.waterLevel = waterLevel;
    job.position = vector3(position);
    job.rotationDegrees = vector3(rotationDeg);
    job.noRadiation = noRadiation;
    if (integrator) {
        job.integrator = integratorFromName(*integrator);
        if (!job.integrator)
            raise({"integrator: unknown '" + *integrator +
                       "' (explicit-euler, semi-implicit-euler, rk4)",
                   ErrorKind::invalidArgument});
    }
    if (mesh && !(density > 0 && fluidDensity > 0 && std::isfinite(density) &&
                  std::isfinite(fluidDensity) && std::isfinite(waterLevel)))
        raise({"density, fluid_density: expected finite numbers > 0; water_level finite",
               ErrorKind::invalidArgument});
    if (mesh && (size < kMinTextureSize || size > kMaxTextureSize))
        raise({"size " + std::to_string(size) + ": out of range", ErrorKind::invalidArgument});
    const cli::Reporter reporter = reporterFor(notes);

    struct Run {
        std::vector<double> rows;  ///< time and trajectoryRow, per frame and body
        std::vector<std::string> bodies;
        std::string device;
        std::size_t steps = 0;
        long frames = 0;
    };
    Result<Run> run = withoutGil([&]() -> Result<Run> {
        Result<cli::PreparedSimulation> prepared = cli::prepareSimulation(job, reporter);
        if (!prepared) return prepared.error();
        World& world = *prepared->world;
        Run r;
        r.frames = prepared->frames;
        r.rows.reserve(static_cast<std::size_t>(r.frames) * world.bodies().size() * 22);
        for (long frame = 0; frame < r.frames; ++frame) {
            if (Status s = cli::advanceFrameChecked(world); !s) return s.error();
            for (const SimulatedBody& b : world.bodies()) {
                r.rows.push_back(world.time());
                const std::array<double, 21> row = cli::trajectoryRow(b);
                r.rows.insert(r.rows.end(), row.begin(), row.end());
                r.bodies.push_back(b.name);
            }
        }
        r.device = world.backend().deviceName();
        r.steps = world.statistics().steps;
        return r;
    });
    Run r = value(std::move(run));
    const py::ssize_t count = static_cast<py::ssize_t>(r.bodies.size());
    py::array_t<double> table({count, py::ssize_t{22}});
    std::copy(r.rows.begin(), r.rows.end(), table.mutable_data());
    py::list columns;
    py::dict out;
    std::string header = cli::kTrajectoryHeader;
    int column = 0;
    for (std::size_t start = 0; start <= header.size();) {
        const std::size_t end = std::min(header.find(',', start), header.size());
        const std::string name = header.substr(start, end - start);
        start = end + 1;
        if (name == "body") continue;
        columns.append(name);
        out[py::str(name)] =
            table[py::make_tuple(py::slice(py::none(), py::none(), py::none()), column++)];
    }
    out["columns"] = columns;
    out["table"] = table;
    out["body"] = py::cast(r.bodies);
    out["device"] = r.device;
    out["steps"] = r.steps;
    out["frames"] = r.frames;
    return out;
}

/// `export` for one or more projects: what the summary's "bodies" lists.
py::list exportProjects(const std::vector<std::string>& projects, const std::string& out,
                        bool compact, bool force, bool check, const py::object& notes) {
    if (out.empty())
        raise(
            {"out: an empty path (it would mean the current folder)", ErrorKind::invalidArgument});
    const cli::Reporter reporter = reporterFor(notes);
    const cli::ExportMode mode{check, force, compact};
    const std::function<void(const std::string&)> notice = [&reporter](const std::string& line) {
        reporter.note(line + "\n");
    };
    struct Done {
        std::string project, body, folder;
        Result<BundleReport> report;
    };
    Result<std::vector<Done>> done = withoutGil([&]() -> Result<std::vector<Done>> {
        std::vector<Done> all;
        std::vector<std::string> folders;
        for (const std::string& path : projects) {
            Result<Project> project = loadProject(path);
            if (!project) return project.error();
            // Folders as `plimsoll export` names them: OUT/<project stem>/<body>/.
            const std::string folder = cli::exportFolderName(project->fileStem, folders);
            folders.push_back(folder);
            for (std::size_t b = 0; b < project->bodies.size(); ++b) {
                const std::filesystem::path where =
                    std::filesystem::path(out) / folder / bundleFolderName(*project, b);
                all.push_back({path, project->bodies[b].name, where.generic_string(),
                               cli::exportBody(*project, b, where, mode, notice)});
            }
        }
        return all;
    });
    py::list entries;
    for (Done& d : value(std::move(done))) {
        // One failed body fails the call, as the command exits 1 (the others are written).
        const BundleReport& r = value(std::move(d.report));
        nlohmann::json entry = cli::bundleReportJson(r);
        entry["project"] = d.project;
        entry["body"] = d.body;
        entry["folder"] = d.folder;
        entry["status"] = check ? (r.outOfDate.empty() ? "up_to_date" : "out_of_date")
                                : (r.unchanged ? "unchanged" : "written");
        if (check) entry["out_of_date"] = r.outOfDate;
        entries.append(fromJson(entry));
    }
    return entries;
}

}  // namespace

[[noreturn]] void raise(const std::string& message, const char* kind) {
    py::object exception = py::handle(errorType)(message);
    exception.attr("kind") = kind;
    exception.attr("message") = message;
    PyErr_SetObject(errorType, exception.ptr());
    throw py::error_already_set();
}

[[noreturn]] void raise(const Error& error) { raise(error.message, errorKindName(error.kind)); }

double unitScale(const Unit& unit) {
    if (!unit) return 0;
    // As the command line's --unit takes it: a name or its number (parseLengthUnit), or the
    // number of metres itself.
    const double* number = std::get_if<double>(&*unit);
    const std::optional<double> metres =
        number ? (std::isfinite(*number) && *number > 0 ? std::optional(*number) : std::nullopt)
               : parseLengthUnit(std::get<std::string>(*unit));
    if (!metres)
        raise({"unit: expected m, cm, mm, km, in, ft, yd or metres per file unit (a number > 0)",
               ErrorKind::invalidArgument});
    return *metres;
}

}  // namespace plimsoll::python

PYBIND11_MODULE(plimsoll, m) {
    using namespace plimsoll::python;
    using namespace pybind11::literals;
    m.doc() =
        "Plimsoll: texture-space buoyancy. The engine's jobs (the command line's, with the "
        "same results and errors) and the runtime's asset and instance API (docs/python.md).";
    // plimsoll.Error: .kind is the engine's ErrorKind name ("io", "format", "schema", "limit",
    // "device", "kernel-build", "invalid-argument", "unsupported"; "runtime" for the runtime
    // library's errors), .message the message the command line prints after "error: ".
    errorType =
        PyErr_NewExceptionWithDoc("plimsoll.Error",
                                  "A Plimsoll failure: .kind (the error kind), .message (what the "
                                  "command line prints after 'error: ')",
                                  PyExc_Exception, nullptr);
    m.attr("Error") = py::handle(errorType);

    m.def("validate", &validate, "mesh"_a, "unit"_a = py::none(),
          "The facts of `plimsoll validate MESH --json` as a dict. Raises plimsoll.Error where the "
          "file cannot be read; an unusable mesh gives usable = False.");
    m.def("bake", &bake, "mesh"_a, "size"_a = 512, "unit"_a = py::none(), "atlas"_a = "auto",
          "max_texel_stretch"_a = py::none(), "notes"_a = py::none(),
          "Bakes a mesh: the sample list the physics sums run over (texel_index, position = PT, "
          "area_vector = AVT, area, coverage) as arrays, with the atlas used and the repairs.");
    m.def("massprops", &massprops, "mesh"_a, "size"_a = 512, "exact"_a = false,
          "density"_a = py::none(), "shell_density"_a = 0.0, "shell_density_map"_a = "",
          "unit"_a = py::none(), "atlas"_a = "auto", "max_texel_stretch"_a = py::none(),
          "body"_a = "", "notes"_a = py::none(),
          "The facts of `plimsoll massprops MESH [--size N | --exact] --json`, or of "
          "`plimsoll massprops PROJECT [--body NAME] --json` (the body as the World weighs it: "
          "its material and painted density and thickness maps); center_of_mass and inertia as "
          "arrays.");
    m.def("buoyancy", &buoyancy, "mesh"_a, "position"_a, "rotation_deg"_a, "water_level"_a = 0.0,
          "velocity"_a = py::none(), "angular_velocity"_a = py::none(), "size"_a = 512,
          "exact"_a = false, "device"_a = "", "fluid_density"_a = 1000.0,
          "drag_coefficient"_a = 1.0, "friction_coefficient"_a = 0.0, "compare_exact"_a = false,
          "unit"_a = py::none(), "atlas"_a = "auto", "notes"_a = py::none(),
          "The facts of `plimsoll buoyancy MESH ... --json`: forces and torques at one pose on "
          "flat water.");
    m.def("hydrostatics", &hydrostatics, "project"_a, "body"_a = "", "exact"_a = false,
          "step_deg"_a = 5.0, "notes"_a = py::none(),
          "The facts of `plimsoll hydrostatics PROJECT --json`: equilibrium, GM, GZ (an (n, 2) "
          "array of heel in degrees and arm in m), the IS Code's criteria.");
    m.def("simulate", &simulate, "project"_a = py::none(), "seconds"_a = py::none(), py::kw_only(),
          "mesh"_a = py::none(), "density"_a = 500.0, "size"_a = 128, "fluid_density"_a = 1000.0,
          "water_level"_a = 0.0, "position"_a = py::none(), "rotation_deg"_a = py::none(),
          "no_radiation"_a = false, "unit"_a = py::none(), "device"_a = "",
          "integrator"_a = py::none(), "notes"_a = py::none(),
          "Runs a project (or one body given by mesh=) as `plimsoll simulate` does. Returns the "
          "columns of `simulate --out` as arrays (time, x, y, z, qw, ...; one row per frame and "
          "body), 'table' (rows x 22), 'body' (the name per row), 'columns', 'device', 'steps'.");
    m.def("export", &exportProjects, "projects"_a, "out"_a, "compact"_a = false, "force"_a = false,
          "check"_a = false, "notes"_a = py::none(),
          "`plimsoll export PROJECT... --out DIR`: a runtime bundle per body in "
          "OUT/<project>/<body>/. Returns the summary's entry per body.");
    m.def(
        "export",
        [](const std::string& project, const std::string& out, bool compact, bool force, bool check,
           const py::object& notes) {
            return exportProjects({project}, out, compact, force, check, notes);
        },
        "project"_a, "out"_a, "compact"_a = false, "force"_a = false, "check"_a = false,
        "notes"_a = py::none());
    bindRuntime(m);
}
