// plimsoll simulate PROJECT | --mesh MESH --density RHO ...: runs a scene headless, writes the
// trajectory (CSV or JSON by extension), prints a one-line summary or, with --json, the final
// state of the first body.
#include "cli/commands.h"

#include "cli/common.h"
#include "cli/jobs.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/project/project.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/scene/world.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>

namespace plimsoll::cli {

namespace {

struct SimulateOptions {
    SimulateJob job;
    std::string out;
    bool json = false;
    std::string integrator;
};

/// The one-body scene the flags describe.
Project projectFromFlags(const SimulateJob& o) {
    Project project;
    project.name = "command line";
    // No project file: messages name the mesh, and no folder, so that nothing (atlas, levels,
    // radiation) is cached beside a made-up one; the mesh's path is taken as given.
    project.sourceName = o.mesh;
    BodyDesc body;
    body.name = std::filesystem::path(o.mesh).stem().string();
    body.mesh = o.mesh;
    body.unitScale = o.unitScale;
    body.textureSize = o.size;
    body.material.density = o.density;
    body.position = o.position;
    body.rotationDegrees = o.rotationDegrees;
    if (o.noRadiation) body.radiation = RadiationDesc{.enabled = false};
    project.bodies.push_back(body);
    project.medium.density = o.fluidDensity;
    project.water = WaterModel::flat(o.waterLevel);
    return project;
}

nlohmann::json bodyJson(const SimulatedBody& b, double time) {
    const Eigen::Quaterniond& q = b.state.orientation;
    return {{"name", b.name},
            {"time", time},
            {"position", vectorJson(b.state.position)},
            {"orientation", {q.w(), q.x(), q.y(), q.z()}},
            {"velocity", vectorJson(linearVelocity(b.state, b.mass))},
            {"angular_velocity", vectorJson(angularVelocity(b.state, b.mass))},
            {"submerged_volume", b.buoyancy.submergedVolume},
            {"buoyant_force", vectorJson(b.buoyancy.pressureForce)},
            {"mass", b.mass.mass},
            {"center_of_mass", vectorJson(b.mass.centerOfMass)}};
}

/// The trajectory file, written as the frames come (a long run must not hold every frame in
/// memory): CSV, one row per frame and body: time, body, centre of mass (world), quaternion
/// (w, x, y, z), velocities, submerged volume, buoyant force, mass, centre of mass (object
/// space); or JSON (by the extension), an array of bodyJson objects.
class TrajectoryWriter {
public:
    TrajectoryWriter(std::ostream& out, bool json) : out_(out), json_(json) {
        out_.precision(10);
        if (json_)
            out_ << "[";
        else
            out_ << kTrajectoryHeader << '\n';
    }
    void frame(double time, const std::vector<SimulatedBody>& bodies) {
        for (const SimulatedBody& b : bodies) json_ ? jsonRow(b, time) : csvRow(b, time);
    }
    void finish() {
        if (json_) out_ << (rows_ ? "\n]\n" : "]\n");
    }
    /// False once a write failed (a full disk): the save then reports the cause.
    bool writing() const { return static_cast<bool>(out_); }

private:
    void csvRow(const SimulatedBody& b, double time) {
        out_ << time << ',' << b.name;
        for (double value : trajectoryRow(b)) out_ << ',' << value;
        out_ << '\n';
    }
    void jsonRow(const SimulatedBody& b, double time) {
        // As the whole array's dump(1): each element one level in.
        const std::string element = reportJson(bodyJson(b, time), 1);
        out_ << (rows_ ? ",\n " : "\n ");
        for (char c : element) {
            out_ << c;
            if (c == '\n') out_ << ' ';
        }
        ++rows_;
    }

    std::ostream& out_;
    bool json_;
    std::size_t rows_ = 0;
};

int runSimulate(const SimulateOptions& o) {
    SimulateJob job = o.job;
    if (job.project.empty() && job.mesh.empty()) {
        std::cerr << "error: give a PROJECT or --mesh\n";
        return kExitUsage;
    }
    if (!o.integrator.empty()) {
        job.integrator = integratorFromName(o.integrator);
        if (!job.integrator) {
            std::cerr << "error: --integrator: unknown '" << o.integrator
                      << "' (explicit-euler, semi-implicit-euler, rk4)\n";
            return kExitUsage;
        }
    }
    Result<PreparedSimulation> prepared = prepareSimulation(job, stderrReporter());
    if (!prepared) {
        std::cerr << "error: " << prepared.error().message << "\n";
        return kExitFailure;
    }
    const Project& project = prepared->project;
    World& world = *prepared->world;

    const long frameCount = prepared->frames;
    const ProgressCallback progress = stderrProgress("simulating");
    const auto start = std::chrono::steady_clock::now();
    // Each frame goes to the trajectory file (a temporary, renamed over --out when the run
    // succeeds) as it is computed. False: the simulation failed (said here); a failed write
    // ends the run early and is said by the save, naming the file and the cause.
    auto run = [&](TrajectoryWriter* trajectory) -> bool {
        for (long frame = 0; frame < frameCount; ++frame) {
            if (Status s = advanceFrameChecked(world); !s.ok()) {
                std::cerr << "error: " << s.error().message << "\n";
                return false;
            }
            if (trajectory) {
                trajectory->frame(world.time(), world.bodies());
                if (!trajectory->writing()) return true;
            }
            if (progress) progress(static_cast<double>(frame + 1) / frameCount);
        }
        if (trajectory) trajectory->finish();
        return true;
    };
    if (o.out.empty()) {
        if (!run(nullptr)) return kExitFailure;
    } else {
        bool simulated = true;
        const Status written = writeFileAtomically(o.out, [&](std::ostream& out) {
            TrajectoryWriter trajectory(out, std::filesystem::path(o.out).extension() == ".json");
            simulated = run(&trajectory);
            return simulated;
        });
        if (!simulated) return kExitFailure;
        if (!written.ok()) {
            std::cerr << "error: " << written.error().message << "\n";
            return kExitFailure;
        }
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const WorldStatistics& stats = world.statistics();
    if (o.json) {
        nlohmann::json out = bodyJson(world.bodies().front(), world.time());
        out["device"] = world.backend().deviceName();
        out["steps"] = stats.steps;
        out["wall_seconds"] = wall;
        std::cout << reportJson(out) << "\n";
    } else {
        const SimulatedBody& b = world.bodies().front();
        std::cout << (project.name.empty() ? "scene" : project.name) << ": " << world.time()
                  << " s simulated in " << wall << " s (" << stats.steps << " steps, "
                  << world.backend().deviceName() << "); " << b.name << " at "
                  << b.state.position.transpose() << " m, submerged " << b.buoyancy.submergedVolume
                  << " m^3; buoyancy evaluations " << stats.buoyancyEvaluations
                  << ", skipped out of water " << stats.skippedOutOfWater << "\n";
    }
    return kExitOk;
}

}  // namespace

Result<PreparedSimulation> prepareSimulation(const SimulateJob& o, const Reporter& reporter) {
    PreparedSimulation prepared;
    Project& project = prepared.project;
    if (!o.project.empty()) {
        Result<Project> loaded = loadProject(o.project);
        if (!loaded) return loaded.error();
        project = std::move(*loaded);
    } else if (!o.mesh.empty()) {
        project = projectFromFlags(o);
    } else {
        return makeError(ErrorKind::invalidArgument, "give a PROJECT or --mesh");
    }
    if (o.integrator) project.simulation.integrator = *o.integrator;
    // Named by its project (or mesh), as every other error of the job is.
    const std::string source = !o.project.empty() ? o.project : o.mesh;
    const double seconds = o.seconds.value_or(project.simulation.duration);
    // Counted in double first: seconds / time_step can exceed every integer (1e300 s, a
    // 1e-300 s step), and converting such a value to an integer is undefined.
    const double frames = std::ceil(seconds / project.simulation.timeStep - 1e-9);
    if (!(frames >= 0) || frames > double(kMaxSimulationFrames)) {
        std::ostringstream message;
        message << source << ": " << seconds << " s at a time step of "
                << project.simulation.timeStep << " s is " << frames
                << " frames, more than the limit kMaxSimulationFrames = " << kMaxSimulationFrames
                << " (limits.h)";
        return makeError(ErrorKind::limit, message.str());
    }
    prepared.frames = static_cast<long>(frames);

    std::string notice;
    Result<std::unique_ptr<BuoyancyBackend>> backend = createBuoyancyBackend(o.device, &notice);
    if (!backend) return backend.error();
    if (!notice.empty()) reporter.note("note: " + notice + "\n");
    // The World keeps its log for the whole run, longer than `reporter` may live: the notes
    // function is held by value.
    const LogFunction log = [notes = reporter.notes](const std::string& line) {
        if (notes) notes(line + "\n");
    };
    Result<Scene> scene = loadScene(project, log, reporter.progress);
    if (!scene) return scene.error();
    Result<std::unique_ptr<World>> created =
        World::create(std::move(*scene), std::move(*backend), log);
    // The scene's own problems (a body no step resolves) name the file it came from.
    if (!created) return withContext(source + ": ", created.error());
    prepared.world = std::move(*created);
    return prepared;
}

Status advanceFrameChecked(World& world) {
    auto at = [&world] {
        std::ostringstream text;
        text << world.time();
        return text.str();
    };
    if (Status s = world.advanceFrame(); !s.ok())
        return withContext("at t = " + at() + " s: ", s.error());
    for (const SimulatedBody& b : world.bodies()) {
        if (!b.state.position.allFinite() || !b.state.orientation.coeffs().allFinite())
            return makeError(ErrorKind::invalidArgument,
                             "body '" + b.name + "' left the finite numbers at t = " + at() + " s");
    }
    return Ok{};
}

std::array<double, 21> trajectoryRow(const SimulatedBody& b) {
    const Eigen::Vector3d v = linearVelocity(b.state, b.mass);
    const Eigen::Vector3d w = angularVelocity(b.state, b.mass);
    const Eigen::Quaterniond& q = b.state.orientation;
    const Eigen::Vector3d& x = b.state.position;
    const Eigen::Vector3d& F = b.buoyancy.pressureForce;
    const Eigen::Vector3d& c = b.mass.centerOfMass;
    return {x.x(), x.y(), x.z(), q.w(),       q.x(), q.y(), q.z(),
            v.x(), v.y(), v.z(), w.x(),       w.y(), w.z(), b.buoyancy.submergedVolume,
            F.x(), F.y(), F.z(), b.mass.mass, c.x(), c.y(), c.z()};
}

void addSimulateCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<SimulateOptions>();
    CLI::App* cmd =
        root.add_subcommand("simulate",
                            "Run a scene headless and write its trajectory (a project, or one body "
                            "given by flags)");
    cmd->add_option("PROJECT", o->job.project, "Project file (*.plim.json)");
    cmd->add_option("--seconds", o->job.seconds,
                    "Simulated time, s (default: the project's duration)")
        ->check(kFiniteNonNegative);
    cmd->add_option("--out", o->out, "Trajectory file: .csv (default) or .json, one row per frame")
        ->check(kNonEmptyPath);
    cmd->add_flag("--json", o->json, "Print the final state of the first body as one JSON object");
    cmd->add_option("--device", o->job.device,
                    "Compute device: fast (CPU), cpu, gpu, an OpenCL index, or reference; default: "
                    "the first GPU, else fast");
    cmd->add_option("--integrator", o->integrator,
                    "explicit-euler, semi-implicit-euler or rk4 (default: the project's)");
    auto* mesh = cmd->add_option("--mesh", o->job.mesh, "One-body scene: the mesh");
    addUnitOption(*cmd, o->job.unitScale)->needs(mesh);
    cmd->add_option("--density", o->job.density, "One-body scene: solid density, kg/m^3")
        ->check(kFinitePositive)
        ->capture_default_str();
    cmd->add_option("--size", o->job.size, "One-body scene: texture size")
        ->check(CLI::Range(kMinTextureSize, kMaxTextureSize))
        ->capture_default_str();
    cmd->add_option("--fluid-density", o->job.fluidDensity, "One-body scene: fluid density, kg/m^3")
        ->check(kFinitePositive)
        ->capture_default_str();
    cmd->add_option("--water-level", o->job.waterLevel, "One-body scene: flat water height, m")
        ->check(kFiniteNumber)
        ->capture_default_str();
    cmd->add_flag("--no-radiation", o->job.noRadiation,
                  "One-body scene: without wave radiation (no panel solve at load; the stand-in "
                  "damping applies, as \"radiation\": false in a project)")
        ->needs(mesh);
    addVectorOption(*cmd, "--position", o->job.position,
                    "One-body scene: position t of the object "
                    "origin (R p + t), m")
        ->type_name("X,Y,Z");
    addVectorOption(*cmd, "--rotation-deg", o->job.rotationDegrees,
                    "One-body scene: rotation Rz Ry Rx, degrees")
        ->type_name("RX,RY,RZ");
    mesh->excludes(cmd->get_option("PROJECT"));
    cmd->callback([o, &selected] { selected = [o] { return runSimulate(*o); }; });
}

}  // namespace plimsoll::cli
