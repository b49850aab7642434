// plimsoll bench --fleet: what a fleet costs a game through the runtime's C ABI. A flooding
// project's body (by default the sample damaged boat) is exported to a bundle once; then, on two
// Gerstner waves, per frame of 1/60 s: one body without its water graph stepped (the water load
// only), the same body flooding (graph step and water load), and N flooding boats, first as
// runtime 2.0 runs them (one bundle, N instances) and then as 1.x had to (N loads), each on one
// thread and on the machine's threads. Memory is what the runtime reports (bundle and instances,
// the evaluation tiles included) and the process's resident growth. Written to
// DIR/bench_fleet.csv.

// The 1.x rows call the runtime's deprecated calls on purpose: they are what 2.0 is measured
// against.
#define PLIMSOLL_RUNTIME_NO_DEPRECATION_WARNINGS
#include "cli/bench.h"
#include "cli/commands.h"

#include "plimsoll/export/bundle.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/project/project.h"

#include "plimsoll_runtime.h"
#include "plimsoll_runtime/runtime.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <thread>
#include <unistd.h>

namespace plimsoll::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Resident memory of this process, bytes (Linux /proc; 0 elsewhere).
double residentBytes() {
    std::ifstream statm("/proc/self/statm");
    double pages = 0, resident = 0;
    if (!(statm >> pages >> resident)) return 0;
    return resident * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

/// The runtime's Gerstner water behind the C callbacks.
void waveHeights(void* user, size_t n, const double* x, const double* z, double t, double* out) {
    const auto& model = *static_cast<const plimsoll_runtime::WaterModel*>(user);
    for (size_t i = 0; i < n; ++i) out[i] = model.height(x[i], z[i], t);
}
double waveHeight(void* user, double x, double z, double t) { return static_cast<const plimsoll_runtime::WaterModel*>(user)->height(x, z, t); }

struct FleetRow {
    std::string name;
    int bodies = 0, bundles = 0, threads = 0;
    double reportedBytes = 0, residentBytes = 0, loadMs = 0, frameMs = 0;
};

using BundlePtr = std::unique_ptr<plimsoll_bundle, decltype(&plimsoll_bundle_destroy)>;
using InstancePtr = std::unique_ptr<plimsoll_instance, decltype(&plimsoll_instance_destroy)>;
using BatchPtr = std::unique_ptr<plimsoll_batch, decltype(&plimsoll_batch_destroy)>;

/// Body i's pose at time t: a grid 12 m apart, heaving and rolling through the waterline.
plimsoll_pose poseOf(int i, double t) {
    const double roll = 0.15 * std::sin(0.9 * t + i), half = 0.5 * roll;
    return {{12.0 * (i % 10), -0.25 + 0.15 * std::sin(1.3 * t + 0.7 * i), 12.0 * (i / 10)},
            {std::cos(half), std::sin(half), 0.0, 0.0}};
}

/// Mean milliseconds of `frames` calls of frame(f), after 5 warm-up calls.
template <class Frame>
double timeFrames(int frames, Frame&& frame) {
    for (int f = 0; f < 5; ++f) frame(f);
    const Clock::time_point start = Clock::now();
    for (int f = 5; f < 5 + frames; ++f) frame(f);
    return 1e3 * std::chrono::duration<double>(Clock::now() - start).count() / frames;
}

/// Loads the bundle and evaluates it once (the evaluation tiles are then built and counted).
BundlePtr loadEvaluated(const fs::path& folder) {
    BundlePtr b(plimsoll_bundle_load(folder.string().c_str(), 1), &plimsoll_bundle_destroy);
    if (!b) return b;
    const plimsoll_pose pose = poseOf(0, 0.0);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(b.get());
    plimsoll_forces forces;
    if (!plimsoll_bundle_evaluate(b.get(), &pose, nullptr, nullptr, &fluid, 0.0, &forces)) b.reset();
    return b;
}

std::uint64_t memoryOf(const plimsoll_bundle* b) {
    plimsoll_bundle_size size{sizeof(plimsoll_bundle_size), 0, 0, 0, 0};
    plimsoll_bundle_size_query(b, &size);
    return size.memory_bytes;
}

void printFleet(const std::vector<FleetRow>& rows) {
    std::vector<std::vector<std::string>> lines = {
        {"case", "bodies", "bundles", "threads", "memory (MB)", "resident (MB)", "load (ms)", "frame (ms)",
         "per body (us)"}};
    for (const FleetRow& r : rows) {
        lines.push_back({r.name, std::to_string(r.bodies), std::to_string(r.bundles), std::to_string(r.threads),
                         format("%.2f", r.reportedBytes / 1048576.0), format("%.1f", r.residentBytes / 1048576.0),
                         format("%.1f", r.loadMs), format("%.3f", r.frameMs),
                         format("%.1f", 1e3 * r.frameMs / r.bodies)});
    }
    printAligned(lines, 1);
}

}  // namespace

int runFleetBench(const BenchOptions& o) {
    const int frames = o.frames > 0 ? o.frames : (o.quick ? 20 : 120);
    const int fleet = o.quick ? 20 : 100;
    Result<Project> project = loadProject(o.fleetProject);
    if (!project) {
        std::cerr << "error: " << project.error().message << "\n";
        return kExitFailure;
    }
    if (!createOutputFolder(o.out)) return kExitFailure;
    const fs::path folder = fs::path(o.out) / "fleet_bundle";
    if (Result<BundleReport> report = writeBodyBundle(*project, 0, folder); !report) {
        std::cerr << "error: " << report.error().message << "\n";
        return kExitFailure;
    }
    plimsoll_runtime::WaterModel waves;
    waves.kind = plimsoll_runtime::WaterModel::Kind::Gerstner;
    waves.waves.resize(2);
    waves.waves[0].amplitude = 0.2;
    waves.waves[0].wavelength = 12.0;
    waves.waves[1].amplitude = 0.08;
    waves.waves[1].wavelength = 5.0;
    waves.waves[1].direction[0] = 0.3;
    waves.waves[1].direction[1] = 1.0;
    waves.waves[1].phase = 1.1;
    plimsoll_water water{};
    water.height = waveHeight;
    water.heights = waveHeights;
    water.user = &waves;
    water.has_bounds = 1;
    water.min_height = waves.minHeight();
    water.max_height = waves.maxHeight();
    const double dt = 1.0 / 60.0;
    const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    std::printf("plimsoll bench --fleet: %s, %d frames of %.4f s on two Gerstner waves, %d hardware threads\n",
                o.fleetProject.c_str(), frames, dt, hardware);

    std::vector<FleetRow> rows;
    const Clock::time_point loadStart = Clock::now();
    const BundlePtr shared = loadEvaluated(folder);
    const double loadMs = 1e3 * std::chrono::duration<double>(Clock::now() - loadStart).count();
    if (!shared) {
        std::cerr << "error: " << plimsoll_runtime_last_error() << "\n";
        return kExitFailure;
    }
    if (plimsoll_graph_node_count(shared.get()) == 0) {
        std::cerr << "error: " << o.fleetProject << ": its first body has no water graph (--fleet needs a flooding body)\n";
        return kExitFailure;
    }
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(shared.get());
    std::size_t permeable = 0;
    {
        std::string error;
        const std::unique_ptr<plimsoll_runtime::Bundle> cpp = plimsoll_runtime::loadBundle(folder.string(), error);
        if (cpp && cpp->graph()) permeable = cpp->graph()->permeableSamples();
    }
    bool failed = false;
    auto check = [&failed](int ok) {
        if (!ok && !failed) std::cerr << "error: " << plimsoll_runtime_last_error() << "\n";
        failed = failed || !ok;
    };

    // One body: the water load alone (dry), then with its graph stepped (flooding).
    {
        InstancePtr one(plimsoll_instance_create(shared.get()), &plimsoll_instance_destroy);
        const std::uint64_t bytes = memoryOf(shared.get()) + plimsoll_instance_memory_bytes(one.get());
        plimsoll_load load;
        const double dry = timeFrames(frames, [&](int f) {
            const plimsoll_pose pose = poseOf(0, f * dt);
            check(plimsoll_instance_water_load(one.get(), &pose, nullptr, &water, &fluid, f * dt, dt, &load));
        });
        rows.push_back({"one body, water load only (dry)", 1, 1, 1, double(bytes), 0, loadMs, dry});
        const double flooding = timeFrames(frames, [&](int f) {
            const plimsoll_pose pose = poseOf(0, f * dt);
            check(plimsoll_instance_graph_step(one.get(), &pose, &water, f * dt, dt) >= 0);
            check(plimsoll_instance_water_load(one.get(), &pose, nullptr, &water, &fluid, f * dt, dt, &load));
        });
        rows.push_back({"one body, flooding (graph step + load)", 1, 1, 1, double(bytes), 0, loadMs, flooding});
        std::printf("flooding / dry: %.2f on the waves (%zu permeable samples, whose heights the waves answer "
                    "in one batched call per step)\n",
                    flooding / dry, permeable);
        // The same on flat water: the graph's own cost without the waves' height evaluations.
        const plimsoll_water flat{};
        const double flatDry = timeFrames(frames, [&](int f) {
            const plimsoll_pose pose = poseOf(0, f * dt);
            check(plimsoll_instance_water_load(one.get(), &pose, nullptr, &flat, &fluid, f * dt, dt, &load));
        });
        const double flatFlooding = timeFrames(frames, [&](int f) {
            const plimsoll_pose pose = poseOf(0, f * dt);
            check(plimsoll_instance_graph_step(one.get(), &pose, &flat, f * dt, dt) >= 0);
            check(plimsoll_instance_water_load(one.get(), &pose, nullptr, &flat, &fluid, f * dt, dt, &load));
        });
        rows.push_back({"one body, water load only (dry), flat water", 1, 1, 1, double(bytes), 0, loadMs, flatDry});
        rows.push_back({"one body, flooding, flat water", 1, 1, 1, double(bytes), 0, loadMs, flatFlooding});
        std::printf("flooding / dry: %.2f on flat water\n", flatFlooding / flatDry);
    }

    // N boats: poses, velocities and loads per body.
    std::vector<plimsoll_pose> poses(fleet);
    std::vector<plimsoll_load> loads(fleet);
    auto posesAt = [&](int f) {
        for (int i = 0; i < fleet; ++i) poses[i] = poseOf(i, f * dt);
    };
    {
        const double before = residentBytes();
        std::vector<InstancePtr> owned;
        std::vector<plimsoll_instance*> instances;
        std::uint64_t bytes = memoryOf(shared.get());
        for (int i = 0; i < fleet; ++i) {
            owned.emplace_back(plimsoll_instance_create(shared.get()), &plimsoll_instance_destroy);
            instances.push_back(owned.back().get());
            bytes += plimsoll_instance_memory_bytes(owned.back().get());
        }
        const double resident = residentBytes() - before;
        for (int threads : {1, hardware}) {
            plimsoll_batch_desc desc{sizeof(plimsoll_batch_desc), threads, nullptr, nullptr, nullptr, 0};
            BatchPtr batch(plimsoll_batch_create(&desc), &plimsoll_batch_destroy);
            const double ms = timeFrames(frames, [&](int f) {
                posesAt(f);
                check(plimsoll_batch_instance_graph_step(batch.get(), fleet, instances.data(), poses.data(), &water,
                                                         f * dt, dt, nullptr));
                check(plimsoll_batch_instance_water_load(batch.get(), fleet, instances.data(), poses.data(), nullptr,
                                                         &water, &fluid, f * dt, dt, loads.data()));
            });
            rows.push_back({"flooding boats, one bundle (2.0)", fleet, 1, threads, double(bytes), resident, loadMs, ms});
            if (hardware == 1) break;
        }
    }
    {
        const double before = residentBytes();
        const Clock::time_point start = Clock::now();
        std::vector<BundlePtr> owned;
        std::vector<plimsoll_bundle*> bundles;
        std::uint64_t bytes = 0;
        for (int i = 0; i < fleet && !failed; ++i) {
            owned.push_back(loadEvaluated(folder));
            check(owned.back() != nullptr);
            if (failed) break;
            bundles.push_back(owned.back().get());
            bytes += memoryOf(owned.back().get());
        }
        const double loads100 = 1e3 * std::chrono::duration<double>(Clock::now() - start).count();
        const double resident = residentBytes() - before;
        for (int threads : {1, hardware}) {
            if (failed) break;
            plimsoll_batch_desc desc{sizeof(plimsoll_batch_desc), threads, nullptr, nullptr, nullptr, 0};
            BatchPtr batch(plimsoll_batch_create(&desc), &plimsoll_batch_destroy);
            const double ms = timeFrames(frames, [&](int f) {
                posesAt(f);
                check(plimsoll_batch_graph_step(batch.get(), fleet, bundles.data(), poses.data(), &water, f * dt, dt,
                                                nullptr));
                check(plimsoll_batch_water_load(batch.get(), fleet, bundles.data(), poses.data(), nullptr, &water,
                                                &fluid, f * dt, dt, loads.data()));
            });
            rows.push_back({"flooding boats, one load each (1.x)", fleet, fleet, threads, double(bytes), resident,
                            loads100, ms});
            if (hardware == 1) break;
        }
    }
    if (failed) return kExitFailure;
    printFleet(rows);
    const fs::path csv = fs::path(o.out) / "bench_fleet.csv";
    const Status written = writeFileAtomically(csv, [&](std::ostream& out) {
        out << "case,bodies,bundles,threads,memory_bytes,resident_bytes,load_ms,frame_ms,us_per_body\n";
        for (const FleetRow& r : rows) {
            out << '"' << r.name << "\"," << r.bodies << ',' << r.bundles << ',' << r.threads << ','
                << format("%.0f", r.reportedBytes) << ',' << format("%.0f", r.residentBytes) << ','
                << format("%.3f", r.loadMs) << ',' << format("%.5f", r.frameMs) << ','
                << format("%.3f", 1e3 * r.frameMs / r.bodies) << '\n';
        }
        return bool(out);
    });
    if (!written.ok()) {
        std::cerr << "error: " << written.error().message << "\n";
        return kExitFailure;
    }
    std::cout << "\nwritten: " << csv.string() << "\n";
    return kExitOk;
}

}  // namespace plimsoll::cli
