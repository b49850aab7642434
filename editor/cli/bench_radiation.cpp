// plimsoll bench --radiation: what radiation (Cummins' equation, docs/radiation.md) costs and
// buys. A 1 m cube of density 250 in water of 1000 kg/m^3, on the C++ reference backend: the
// load-time panel method (panels, frequencies, seconds), the World's time per integration step
// with and without radiation, and the time each run needs to settle (|v| < 1 mm/s) after a
// release 0.35 m above its rest height. Written to DIR/bench_radiation.csv.
#include "cli/bench.h"
#include "cli/commands.h"

#include "plimsoll/compute/compute.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/project/project.h"
#include "plimsoll/project/scene_loader.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/scene_radiation.h"
#include "plimsoll/scene/world.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <utility>

namespace plimsoll::cli {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

struct RadiationRun {
    double secondsPerStep = 0;
    double settleTime = -1;  ///< s, last time |v| >= 1 mm/s; -1: never that fast
    double finalSpeed = 0;
};

/// `seconds` of simulated time of `scene`; null on failure (printed).
std::optional<RadiationRun> runScene(const Scene& scene, double seconds) {
    Result<std::unique_ptr<World>> world = World::create(scene, createReferenceBackend());
    if (!world) {
        std::cerr << "error: " << world.error().message << "\n";
        return std::nullopt;
    }
    RadiationRun run;
    const int frames = static_cast<int>(std::round(seconds / scene.simulation.timeStep));
    const Clock::time_point start = Clock::now();
    for (int f = 0; f < frames; ++f) {
        if (Status s = (*world)->advanceFrame(); !s) {
            std::cerr << "error: " << s.error().message << "\n";
            return std::nullopt;
        }
        const SimulatedBody& b = (*world)->bodies()[0];
        run.finalSpeed = linearVelocity(b.state, b.mass).norm();
        if (run.finalSpeed >= 1e-3) run.settleTime = (*world)->time();
    }
    run.secondsPerStep =
        secondsSince(start) / std::max<std::size_t>(1, (*world)->statistics().steps);
    return run;
}

/// The panel solve of every body of the sample projects (`folder`/*.plim.json) at its default
/// settings (or the project's own "radiation" settings) on one thread, no cache: a table row
/// and a CSV line per body. False when a project does not load.
bool timeSampleBodies(const std::filesystem::path& folder,
                      std::vector<std::vector<std::string>>& lines, std::string& csv) {
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() > 10 && name.ends_with(".plim.json")) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const std::filesystem::path& file : files) {
        Result<Project> project = loadProject(file);
        if (!project) {
            std::cerr << "error: " << project.error().message << "\n";
            return false;
        }
        for (std::size_t i = 0; i < project->bodies.size(); ++i) {
            const std::string body = file.filename().string() + " " + project->bodies[i].name;
            const RadiationDesc asked = project->bodies[i].radiation.value_or(RadiationDesc{});
            Project bare = *project;
            bare.bodies[i].radiation = RadiationDesc{.enabled = false};  // the solve is timed below
            Result<SceneBody> loaded = loadSceneBody(bare, i);
            if (!loaded) {
                std::cerr << "error: " << loaded.error().message << "\n";
                return false;
            }
            if (!project->bodies[i].radiates()) {
                lines.push_back({body, "-", "-", "-", "-", "radiation turned off by the project"});
                continue;
            }
            if (!project->bodies[i].radiationRequired()) {
                if (std::optional<std::string> why =
                        defaultRadiationInapplicable(*loaded, project->medium)) {
                    lines.push_back(
                        {body, "-", "-", "-", "-", "radiation off by default: " + *why});
                    continue;
                }
            }
            const double cpuStart = threadCpuSeconds();
            const Clock::time_point start = Clock::now();
            Result<BodyRadiation> r = computeBodyRadiation(*loaded, asked, project->medium,
                                                           project->simulation.gravity, {}, 1);
            const double wall = secondsSince(start), cpu = threadCpuSeconds() - cpuStart;
            if (!r) {
                lines.push_back({body, "-", "-", "-", "-", r.error().message});
                csv += body + ",0,0,0,0\n";
                continue;
            }
            lines.push_back({body, std::to_string(r->panelCount),
                             std::to_string(r->coefficients.size()), format("%.3f", cpu),
                             format("%.3f", wall), ""});
            csv += body + "," + std::to_string(r->panelCount) + "," +
                   std::to_string(r->coefficients.size()) + "," + format("%.6g", cpu) + "," +
                   format("%.6g", wall) + "\n";
        }
    }
    return true;
}

}  // namespace

int runRadiationBench(const BenchOptions& o) {
    {
        std::printf(
            "panel solve of each sample body (projects/*.plim.json) at its default settings, one "
            "thread, no cache:\n");
        std::vector<std::vector<std::string>> lines{
            {"body", "panels", "frequencies", "CPU s", "wall s", "note"}};
        std::string csv = "body,panels,frequencies,cpu_seconds,wall_seconds\n";
        if (!timeSampleBodies(o.projects, lines, csv)) return kExitFailure;
        printAligned(lines, 1);
        if (!createOutputFolder(o.out)) return kExitFailure;
        const std::filesystem::path file =
            std::filesystem::path(o.out) / "bench_radiation_samples.csv";
        if (Status s =
                writeFileAtomically(file, [&](std::ostream& out) { return bool(out << csv); });
            !s) {
            std::cerr << "error: " << s.error().message << "\n";
            return kExitFailure;
        }
        std::printf("wrote %s\n", file.string().c_str());
    }
    BodyDesc desc;
    desc.name = "cube";
    desc.mesh = "1 m cube (generated)";
    desc.textureSize = 128;
    desc.material.density = 250;
    Scene scene;
    scene.water = WaterModel::flat(0.0);
    BodyParts parts;
    parts.mesh = std::make_shared<const TriangleMesh>(makeBox(Eigen::Vector3d(1, 1, 1)));
    Result<SceneBody> body = bakeSceneBody(desc, std::move(parts));
    if (!body) {
        std::cerr << "error: " << body.error().message << "\n";
        return kExitFailure;
    }
    // Faces split to 16 panels each: the default panel edge (cbrt(V) / 2, docs/radiation.md)
    // would make a few hundred with the lid, a bake several times longer.
    const RadiationDesc settings{.panelEdge = 0.5, .frequencies = 12};
    const Clock::time_point bakeStart = Clock::now();
    Result<BodyRadiation> radiation =
        computeBodyRadiation(*body, settings, scene.medium, scene.simulation.gravity);
    const double bakeSeconds = secondsSince(bakeStart);
    if (!radiation) {
        std::cerr << "error: " << radiation.error().message << "\n";
        return kExitFailure;
    }
    std::printf(
        "radiation of a 1 m cube of density 250 (%d^2 textures, reference backend): %zu panels, "
        "%zu "
        "frequencies (panel edge %g m) and A_inf in %.3f s\n",
        desc.textureSize, radiation->panelCount, radiation->coefficients.size(), settings.panelEdge,
        bakeSeconds);
    const auto shared = std::make_shared<const BodyRadiation>(std::move(*radiation));
    body->desc.position = {0, shared->restHeight + 0.35, 0};
    // The quick run only times steps; the full one also waits for both runs to settle.
    const double seconds = o.quick ? 2.0 : 90.0;
    std::vector<std::vector<std::string>> lines{
        {"run", "s/step", "settled after (s)", "|v| at end (m/s)"}};
    std::string csv = "run,seconds_per_step,settle_time_s,final_speed_m_s\n";
    for (const bool on : {false, true}) {
        Scene s = scene;
        SceneBody b = *body;
        if (on) {
            b.desc.radiation = settings;
            b.radiation = shared;
        }
        s.bodies.push_back(std::move(b));
        const std::optional<RadiationRun> run = runScene(s, seconds);
        if (!run) return kExitFailure;
        const char* name = on ? "with radiation (and drag and the stand-in)"
                              : "without (drag and the linear_damping stand-in)";
        const std::string settled = run->settleTime < 0 ? "at once"
                                    : run->finalSpeed >= 1e-3
                                        ? "not in " + format("%.0f", seconds) + " s"
                                        : format("%.2f", run->settleTime);
        lines.push_back(
            {name, format("%.3g", run->secondsPerStep), settled, format("%.2e", run->finalSpeed)});
        csv += std::string(on ? "with" : "without") + "," + format("%.6g", run->secondsPerStep) +
               "," + format("%.6g", run->finalSpeed >= 1e-3 ? -1.0 : run->settleTime) + "," +
               format("%.6g", run->finalSpeed) + "\n";
    }
    printAligned(lines, 1);
    if (!createOutputFolder(o.out)) return kExitFailure;
    const std::filesystem::path file = std::filesystem::path(o.out) / "bench_radiation.csv";
    if (Status s = writeFileAtomically(file, [&](std::ostream& out) { return bool(out << csv); });
        !s) {
        std::cerr << "error: " << s.error().message << "\n";
        return kExitFailure;
    }
    std::printf("wrote %s\n", file.string().c_str());
    return kExitOk;
}

}  // namespace plimsoll::cli
