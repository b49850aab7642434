// plimsoll bench --radiation: what radiation (Cummins' equation, docs/radiation.md) costs and
// buys. A 1 m cube of density 250 in water of 1000 kg/m^3, on the C++ reference backend: the
// load-time panel method (panels, frequencies, seconds), the World's time per integration step
// with and without radiation, and the time each run needs to settle (|v| < 1 mm/s) after a
// release 0.35 m above its rest height. Written to DIR/bench_radiation.csv.
#include "cli/bench.h"
#include "cli/commands.h"

#include "plimsoll/compute/compute.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/scene_radiation.h"
#include "plimsoll/scene/world.h"

#include <chrono>
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
    run.secondsPerStep = secondsSince(start) / std::max<std::size_t>(1, (*world)->statistics().steps);
    return run;
}

}  // namespace

int runRadiationBench(const BenchOptions& o) {
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
    std::printf("radiation of a 1 m cube of density 250 (%d^2 textures, reference backend): %zu panels, %zu "
                "frequencies (panel edge %g m) and A_inf in %.3f s\n",
                desc.textureSize, radiation->panelCount, radiation->coefficients.size(), settings.panelEdge, bakeSeconds);
    const auto shared = std::make_shared<const BodyRadiation>(std::move(*radiation));
    body->desc.position = {0, shared->restHeight + 0.35, 0};
    // The quick run only times steps; the full one also waits for both runs to settle.
    const double seconds = o.quick ? 2.0 : 90.0;
    std::vector<std::vector<std::string>> lines{{"run", "s/step", "settled after (s)", "|v| at end (m/s)"}};
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
        const char* name = on ? "with radiation (and drag and the stand-in)" : "without (drag and the linear_damping stand-in)";
        const std::string settled = run->settleTime < 0 ? "at once"
                                    : run->finalSpeed >= 1e-3 ? "not in " + format("%.0f", seconds) + " s"
                                                              : format("%.2f", run->settleTime);
        lines.push_back({name, format("%.3g", run->secondsPerStep), settled, format("%.2e", run->finalSpeed)});
        csv += std::string(on ? "with" : "without") + "," + format("%.6g", run->secondsPerStep) + "," +
               format("%.6g", run->finalSpeed >= 1e-3 ? -1.0 : run->settleTime) + "," +
               format("%.6g", run->finalSpeed) + "\n";
    }
    printAligned(lines, 1);
    if (!createOutputFolder(o.out)) return kExitFailure;
    const std::filesystem::path file = std::filesystem::path(o.out) / "bench_radiation.csv";
    if (Status s = writeFileAtomically(file, [&](std::ostream& out) { return bool(out << csv); }); !s) {
        std::cerr << "error: " << s.error().message << "\n";
        return kExitFailure;
    }
    std::printf("wrote %s\n", file.string().c_str());
    return kExitOk;
}

}  // namespace plimsoll::cli
