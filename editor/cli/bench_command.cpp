// plimsoll bench: the command line. What it measures lives one measurement to a file
// (bench.h): the speed against accuracy table by default, --integrators, --realtime.
#include "cli/commands.h"

#include "cli/bench.h"
#include "cli/bench_realtime.h"
#include "cli/common.h"
#include "plimsoll/core/limits.h"

#include <memory>

namespace plimsoll::cli {

void addBenchCommand(CLI::App& root, CommandRunner& selected) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* cmd = root.add_subcommand(
        "bench",
        "Speed against accuracy: time per frame and error against the exact method, "
        "per texture size and compute device");
    CLI::Option* sizes =
        cmd->add_option("--sizes", o->sizes,
                        "Texture sizes, comma separated (default 32,64,...,2048, and 4096 when "
                        "there is a GPU; the reference backend runs up to 512)")
            ->delimiter(',')
            ->check(CLI::Range(kMinTextureSize, kMaxTextureSize));
    cmd->add_option("--frames", o->frames,
                    "Timed frames per row, after 5 warm-up frames (default 50, 10 with --quick)")
        ->check(kFinitePositive);
    cmd->add_option("--out", o->out,
                    "Folder for bench.csv and bench.svg (bench_integrators.csv with --integrators)")
        ->capture_default_str()
        ->check(kNonEmptyPath);
    cmd->add_option("--mesh", o->mesh,
                    "Mesh with UVs benchmarked beside the sample sphere (skipped when absent)")
        ->capture_default_str();
    cmd->add_flag("--quick", o->quick,
                  "Sizes 32 to 256 and 10 frames (with --integrators: 5 s simulated): a smoke "
                  "test");
    cmd->add_flag("--integrators", o->integrators,
                  "Only the integrators' trade instead: energy drift of a floating box and time "
                  "per step for each integrator at dt 1/240, 1/60, 1/15 s over 30 s "
                  "(DIR/bench_integrators.csv)");
    cmd->add_flag("--realtime", o->realtime,
                  "Only the real-time table instead: at rest / moving on flat water / moving on "
                  "waves, per method, size and body count, time and error side by side "
                  "(DIR/realtime.csv, DIR/realtime.svg)");
    cmd->add_option("--scenario", o->scenarios,
                    "With --realtime: only these scenarios (rest, moving, waves), comma separated")
        ->delimiter(',')
        ->check(CLI::IsMember({"rest", "moving", "waves"}));
    cmd->add_option("--method", o->methods,
                    "With --realtime: only the methods whose name starts with one of these "
                    "(reference, fast CPU, fast CPU (wave grid N) and fast CPU (tiles N): the "
                    "fast path with another water grid or tile size, OpenCL N CPU or GPU, OpenCL "
                    "N ... (wave tol T): the device with another wave tolerance, OpenCL N ... "
                    "(spin wait): the device polling for its totals instead of blocking, OpenCL N "
                    "GPU (items K): K entries a work-item instead of 8, exact plane clip, "
                    "per-triangle wave clip), "
                    "comma separated")
        ->delimiter(',');
    cmd->add_option("--bench-mesh", o->meshes,
                    "With --realtime: only these meshes (sphere, buoy), comma separated")
        ->delimiter(',')
        ->check(CLI::IsMember({"sphere", "buoy"}));
    cmd->add_option("--bodies", o->bodies,
                    "With --realtime: only these body counts (1, 100, 1000), comma separated")
        ->delimiter(',')
        ->check(CLI::IsMember({1, 100, 1000}));
    cmd->add_flag("--radiation", o->radiation,
                  "Only radiation instead: the panel solve's time for every sample project's body "
                  "on one thread (DIR/bench_radiation_samples.csv), the panel method's time for a "
                  "1 m cube, the World's time per step with and without radiation, and when each "
                  "settles after a 0.35 m drop (DIR/bench_radiation.csv)");
    cmd->add_option("--projects", o->projects,
                    "With --radiation: the folder of the sample projects whose bodies are timed")
        ->capture_default_str()
        ->check(kNonEmptyPath);
    cmd->add_flag(
        "--fleet", o->fleet,
        "Only the runtime's fleet table instead: one dry body, one flooding body, and 100 "
        "flooding boats as one bundle with 100 instances against 100 loads, memory and "
        "time per frame on waves (DIR/bench_fleet.csv)");
    cmd->add_flag("--scene", o->scene,
                  "Only the World's scene table instead: 1000 bodies at rest on flat water (100 "
                  "with --quick), time per frame with sleeping off and asleep "
                  "(DIR/bench_scene.csv)");
    cmd->add_option("--fleet-project", o->fleetProject,
                    "With --fleet: the project whose first body (with a water graph) is the boat")
        ->capture_default_str()
        ->check(kNonEmptyPath);
    cmd->callback([o, sizes, &selected] {
        o->sizesGiven = sizes->count() > 0;
        selected = [o] {
            if (o->realtime) {
                RealtimeBenchOptions r;
                r.out = o->out;
                r.quick = o->quick;
                r.frames = o->frames;
                if (o->sizesGiven) r.sizes = o->sizes;
                r.scenarios = o->scenarios;
                r.methods = o->methods;
                r.meshes = o->meshes;
                r.bodies = o->bodies;
                return runRealtimeBench(r);
            }
            if (o->radiation) return runRadiationBench(*o);
            if (o->fleet) return runFleetBench(*o);
            if (o->scene) return runSceneBench(*o);
            return o->integrators ? runIntegratorBench(*o) : runAccuracyBench(*o);
        };
    });
}

}  // namespace plimsoll::cli
