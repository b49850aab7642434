// plimsoll bench --fleet: what a fleet costs a game through the runtime's C ABI. A flooding
// project's body (by default the sample damaged boat) is exported to a bundle once; then, on two
// Gerstner waves, per frame of 1/60 s: one body without its water graph stepped (the water load
// only), the same body flooding (graph step and water load), and N flooding boats, first as
// runtime 2.0 runs them (one bundle, N instances) and then as 1.x had to (N loads), each on one
// thread and on the machine's threads. Memory is what the runtime reports (bundle and instances,
// the evaluation tiles included) and the process's resident growth. Written to
// DIR/bench_fleet.csv. The one-body rows also give the thread's CPU time (the wall clock on a
// shared machine counts other processes too) and the flooding row's ratio to the dry one.

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

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <thread>
#include <time.h>
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

/// Heights the water's callbacks answered (counted, not timed: a clock read per call would
/// cost more than the small batches it measures).
std::atomic<long long> heightsAsked{0};

/// The runtime's Gerstner water behind the C callbacks.
void waveHeights(void* user, size_t n, const double* x, const double* z, double t, double* out) {
    heightsAsked.fetch_add(static_cast<long long>(n), std::memory_order_relaxed);
    const auto& model = *static_cast<const plimsoll_runtime::WaterModel*>(user);
    for (size_t i = 0; i < n; ++i) out[i] = model.height(x[i], z[i], t);
}
double waveHeight(void* user, double x, double z, double t) {
    heightsAsked.fetch_add(1, std::memory_order_relaxed);
    return static_cast<const plimsoll_runtime::WaterModel*>(user)->height(x, z, t);
}

/// Seconds one height of `model` takes (mean of 20000 over a 20 m square).
double secondsPerHeight(const plimsoll_runtime::WaterModel& model) {
    double sink = 0;
    const Clock::time_point start = Clock::now();
    for (int i = 0; i < 20000; ++i) sink += model.height(0.001 * i, 0.0007 * i, 0.01 * i);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count() / 20000;
    return sink == 12345.678 ? 0.0 : seconds;  // keeps the loop
}

struct FleetRow {
    std::string name;
    int bodies = 0, bundles = 0, threads = 0;
    double reportedBytes = 0, residentBytes = 0, loadMs = 0, frameMs = 0;
    // Only where all the work runs on the calling thread (the one-body rows); 0 elsewhere, where
    // the batch's workers would not be counted.
    double cpuMs = 0;
    // Flooding rows: their time over the dry row's on the same water (wall, thread-CPU).
    double wallRatio = 0, cpuRatio = 0;
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

struct FrameTimes {
    double wallMs = 0, cpuMs = 0;
};

/// Mean milliseconds of `frames` calls of frame(f), after 5 warm-up calls: wall and this
/// thread's CPU.
template <class Frame>
FrameTimes timeFrames(int frames, Frame&& frame) {
    for (int f = 0; f < 5; ++f) frame(f);
    const double cpuStart = threadCpuSeconds();
    const Clock::time_point start = Clock::now();
    for (int f = 5; f < 5 + frames; ++f) frame(f);
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    const double cpu = threadCpuSeconds() - cpuStart;
    return {1e3 * wall / frames, 1e3 * cpu / frames};
}

/// Loads the bundle and evaluates it once (the evaluation tiles are then built and counted).
BundlePtr loadEvaluated(const fs::path& folder) {
    BundlePtr b(plimsoll_bundle_load(folder.string().c_str(), 1), &plimsoll_bundle_destroy);
    if (!b) return b;
    const plimsoll_pose pose = poseOf(0, 0.0);
    const plimsoll_fluid fluid = plimsoll_bundle_default_fluid(b.get());
    plimsoll_forces forces;
    if (!plimsoll_bundle_evaluate(b.get(), &pose, nullptr, nullptr, &fluid, 0.0, &forces))
        b.reset();
    return b;
}

std::uint64_t memoryOf(const plimsoll_bundle* b) {
    plimsoll_bundle_size size{sizeof(plimsoll_bundle_size), 0, 0, 0, 0};
    plimsoll_bundle_size_query(b, &size);
    return size.memory_bytes;
}

void printFleet(const std::vector<FleetRow>& rows) {
    std::vector<std::vector<std::string>> lines = {
        {"case", "bodies", "bundles", "threads", "memory (MB)", "resident (MB)", "load (ms)",
         "frame (ms)", "per body (us)", "CPU per body (us)", "flooding / dry (wall)",
         "flooding / dry (CPU)"}};
    for (const FleetRow& r : rows) {
        lines.push_back({r.name, std::to_string(r.bodies), std::to_string(r.bundles),
                         std::to_string(r.threads), format("%.2f", r.reportedBytes / 1048576.0),
                         format("%.1f", r.residentBytes / 1048576.0), format("%.1f", r.loadMs),
                         format("%.3f", r.frameMs), format("%.1f", 1e3 * r.frameMs / r.bodies),
                         r.cpuMs > 0 ? format("%.1f", 1e3 * r.cpuMs / r.bodies) : "",
                         r.wallRatio > 0 ? format("%.2f", r.wallRatio) : "",
                         r.cpuRatio > 0 ? format("%.2f", r.cpuRatio) : ""});
    }
    printAligned(lines, 1);
}

/// Two Gerstner waves, the runtime's own model, and the C water that asks it.
struct Waves {
    plimsoll_runtime::WaterModel model;
    plimsoll_water water{};
    Waves() {
        model.kind = plimsoll_runtime::WaterModel::Kind::Gerstner;
        model.waves.resize(2);
        model.waves[0].amplitude = 0.2;
        model.waves[0].wavelength = 12.0;
        model.waves[1].amplitude = 0.08;
        model.waves[1].wavelength = 5.0;
        model.waves[1].direction[0] = 0.3;
        model.waves[1].direction[1] = 1.0;
        model.waves[1].phase = 1.1;
        water.height = waveHeight;
        water.heights = waveHeights;
        water.user = &model;
        water.has_bounds = 1;
        water.min_height = model.minHeight();
        water.max_height = model.maxHeight();
    }
    Waves(const Waves&) = delete;
    Waves& operator=(const Waves&) = delete;
};

/// The measurements of one run, each adding its rows.
class FleetBench {
public:
    FleetBench(fs::path folder, const plimsoll_bundle* shared, double loadMs, int frames, int fleet)
        : folder_(std::move(folder)),
          shared_(shared),
          fluid_(plimsoll_bundle_default_fluid(shared)),
          loadMs_(loadMs),
          frames_(frames),
          fleet_(fleet),
          poses_(fleet),
          loads_(fleet) {}

    /// One body: the water load alone (dry), then with its graph stepped (flooding), on the waves
    /// and on flat water (the graph's own cost without the waves' heights).
    void oneBody(std::size_t permeable) {
        InstancePtr one(plimsoll_instance_create(shared_), &plimsoll_instance_destroy);
        const double bytes = double(memoryOf(shared_) + plimsoll_instance_memory_bytes(one.get()));
        const plimsoll_water flat{};
        double ratio[2] = {0, 0}, cpuRatio[2] = {0, 0}, own = 0;
        for (int wavy = 1; wavy >= 0; --wavy) {
            const plimsoll_water& water = wavy ? waves_.water : flat;
            heightsAsked = 0;
            const FrameTimes dry = timeFrames(frames_, [&](int f) { load(one.get(), water, f); });
            const double dryHeights = double(heightsAsked.exchange(0)) / (frames_ + 5);
            const FrameTimes flooding = timeFrames(frames_, [&](int f) {
                const plimsoll_pose pose = poseOf(0, f * kDt);
                check(plimsoll_instance_graph_step(one.get(), &pose, &water, f * kDt, kDt) >= 0);
                load(one.get(), water, f);
            });
            const double floodingHeights = double(heightsAsked.exchange(0)) / (frames_ + 5);
            if (wavy) {
                // The runtime's own time: less the heights asked times what one costs the water.
                const double ms = 1e3 * secondsPerHeight(waves_.model);
                own = (flooding.wallMs - floodingHeights * ms) /
                      std::max(dry.wallMs - dryHeights * ms, 1e-9);
                std::printf("heights asked per frame: %.0f dry, %.0f flooding, %.0f ns each\n",
                            dryHeights, floodingHeights, 1e6 * ms);
            }
            const std::string where = wavy ? "" : ", flat water";
            ratio[wavy] = flooding.wallMs / dry.wallMs;
            cpuRatio[wavy] = flooding.cpuMs / std::max(dry.cpuMs, 1e-12);
            rows_.push_back({"one body, water load only (dry)" + where, 1, 1, 1, bytes, 0, loadMs_,
                             dry.wallMs, dry.cpuMs});
            rows_.push_back({"one body, flooding (graph step + load)" + where, 1, 1, 1, bytes, 0,
                             loadMs_, flooding.wallMs, flooding.cpuMs, ratio[wavy],
                             cpuRatio[wavy]});
        }
        std::printf(
            "flooding / dry: %.2f on the waves (%zu permeable samples, the water asked in one "
            "batched call per step at the exchange lattice's nodes about them; %.2f without the "
            "time the water takes to answer), %.2f on flat water; in thread-CPU time %.2f on the "
            "waves, %.2f on flat water\n",
            ratio[1], permeable, own, ratio[0], cpuRatio[1], cpuRatio[0]);
    }

    /// The fleet as runtime 2.0 runs it: one bundle, one instance per boat.
    void sharedFleet() {
        const double before = residentBytes();
        std::vector<InstancePtr> owned;
        std::vector<plimsoll_instance*> instances;
        double bytes = double(memoryOf(shared_));
        for (int i = 0; i < fleet_; ++i) {
            owned.emplace_back(plimsoll_instance_create(shared_), &plimsoll_instance_destroy);
            instances.push_back(owned.back().get());
            bytes += double(plimsoll_instance_memory_bytes(owned.back().get()));
        }
        const double resident = residentBytes() - before;
        for (int threads : threadCounts()) {
            const double ms = timeBatches(threads, [&](plimsoll_batch* batch, int f) {
                check(plimsoll_batch_instance_graph_step(batch, fleet_, instances.data(),
                                                         poses_.data(), &waves_.water, f * kDt, kDt,
                                                         nullptr));
                check(plimsoll_batch_instance_water_load(batch, fleet_, instances.data(),
                                                         poses_.data(), nullptr, &waves_.water,
                                                         &fluid_, f * kDt, kDt, loads_.data()));
            });
            rows_.push_back({"flooding boats, one bundle (2.0)", fleet_, 1, threads, bytes,
                             resident, loadMs_, ms});
        }
    }

    /// The fleet as runtime 1.x had to run it: one load per boat.
    void separateFleet() {
        const double before = residentBytes();
        const Clock::time_point start = Clock::now();
        std::vector<BundlePtr> owned;
        std::vector<plimsoll_bundle*> bundles;
        double bytes = 0;
        for (int i = 0; i < fleet_ && !failed_; ++i) {
            owned.push_back(loadEvaluated(folder_));
            check(owned.back() != nullptr);
            if (failed_) return;
            bundles.push_back(owned.back().get());
            bytes += double(memoryOf(owned.back().get()));
        }
        const double loadMs = 1e3 * std::chrono::duration<double>(Clock::now() - start).count();
        const double resident = residentBytes() - before;
        for (int threads : threadCounts()) {
            const double ms = timeBatches(threads, [&](plimsoll_batch* batch, int f) {
                check(plimsoll_batch_graph_step(batch, fleet_, bundles.data(), poses_.data(),
                                                &waves_.water, f * kDt, kDt, nullptr));
                check(plimsoll_batch_water_load(batch, fleet_, bundles.data(), poses_.data(),
                                                nullptr, &waves_.water, &fluid_, f * kDt, kDt,
                                                loads_.data()));
            });
            rows_.push_back({"flooding boats, one load each (1.x)", fleet_, fleet_, threads, bytes,
                             resident, loadMs, ms});
        }
    }

    bool failed() const { return failed_; }
    const std::vector<FleetRow>& rows() const { return rows_; }

private:
    static constexpr double kDt = 1.0 / 60.0;

    void check(int ok) {
        if (!ok && !failed_) std::cerr << "error: " << plimsoll_runtime_last_error() << "\n";
        failed_ = failed_ || !ok;
    }
    void load(const plimsoll_instance* body, const plimsoll_water& water, int f) {
        const plimsoll_pose pose = poseOf(0, f * kDt);
        plimsoll_load out;
        check(plimsoll_instance_water_load(body, &pose, nullptr, &water, &fluid_, f * kDt, kDt,
                                           &out));
    }
    static std::vector<int> threadCounts() {
        const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
        return hardware > 1 ? std::vector<int>{1, hardware} : std::vector<int>{1};
    }
    /// Mean milliseconds per frame of step(batch, frame) on a batch of `threads`, the boats at
    /// their poses of the frame.
    template <class Step>
    double timeBatches(int threads, Step&& step) {
        plimsoll_batch_desc desc{
            sizeof(plimsoll_batch_desc), threads, nullptr, nullptr, nullptr, 0};
        BatchPtr batch(plimsoll_batch_create(&desc), &plimsoll_batch_destroy);
        return timeFrames(frames_,
                          [&](int f) {
                              for (int i = 0; i < fleet_; ++i) poses_[i] = poseOf(i, f * kDt);
                              step(batch.get(), f);
                          })
            .wallMs;
    }

    fs::path folder_;
    const plimsoll_bundle* shared_;
    plimsoll_fluid fluid_;
    Waves waves_;
    double loadMs_;
    int frames_, fleet_;
    std::vector<plimsoll_pose> poses_;
    std::vector<plimsoll_load> loads_;
    std::vector<FleetRow> rows_;
    bool failed_ = false;
};

bool writeFleetCsv(const fs::path& csv, const std::vector<FleetRow>& rows) {
    const Status written = writeFileAtomically(csv, [&](std::ostream& out) {
        out << "case,bodies,bundles,threads,memory_bytes,resident_bytes,load_ms,frame_ms,us_per_"
               "body,cpu_us_per_body,flooding_over_dry_wall,flooding_over_dry_cpu\n";
        for (const FleetRow& r : rows) {
            out << '"' << r.name << "\"," << r.bodies << ',' << r.bundles << ',' << r.threads << ','
                << format("%.0f", r.reportedBytes) << ',' << format("%.0f", r.residentBytes) << ','
                << format("%.3f", r.loadMs) << ',' << format("%.5f", r.frameMs) << ','
                << format("%.3f", 1e3 * r.frameMs / r.bodies) << ','
                << (r.cpuMs > 0 ? format("%.3f", 1e3 * r.cpuMs / r.bodies) : "") << ','
                << (r.wallRatio > 0 ? format("%.4f", r.wallRatio) : "") << ','
                << (r.cpuRatio > 0 ? format("%.4f", r.cpuRatio) : "") << '\n';
        }
        return bool(out);
    });
    if (!written.ok()) std::cerr << "error: " << written.error().message << "\n";
    return written.ok();
}

/// Permeable samples of the bundle (the exchange asks the water's height on the lattice nodes
/// about them).
std::size_t permeableSamples(const fs::path& folder) {
    std::string error;
    const std::unique_ptr<plimsoll_runtime::Bundle> cpp =
        plimsoll_runtime::loadBundle(folder.string(), error);
    return cpp && cpp->graph() ? cpp->graph()->permeableSamples() : 0;
}

}  // namespace

// The fleet's one-body rows by wall clock scatter by a factor of two on a shared machine.
double threadCpuSeconds() {
    timespec t{};
    ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

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
    std::printf(
        "plimsoll bench --fleet: %s, %d frames of 1/60 s on two Gerstner waves, %u hardware "
        "threads\n",
        o.fleetProject.c_str(), frames, std::max(1u, std::thread::hardware_concurrency()));
    const Clock::time_point loadStart = Clock::now();
    const BundlePtr shared = loadEvaluated(folder);
    const double loadMs = 1e3 * std::chrono::duration<double>(Clock::now() - loadStart).count();
    if (!shared) {
        std::cerr << "error: " << plimsoll_runtime_last_error() << "\n";
        return kExitFailure;
    }
    if (plimsoll_graph_node_count(shared.get()) == 0) {
        std::cerr << "error: " << o.fleetProject
                  << ": its first body has no water graph (--fleet needs a flooding body)\n";
        return kExitFailure;
    }
    FleetBench bench(folder, shared.get(), loadMs, frames, fleet);
    bench.oneBody(permeableSamples(folder));
    if (!bench.failed()) bench.sharedFleet();
    if (!bench.failed()) bench.separateFleet();
    if (bench.failed()) return kExitFailure;
    printFleet(bench.rows());
    const fs::path csv = fs::path(o.out) / "bench_fleet.csv";
    if (!writeFleetCsv(csv, bench.rows())) return kExitFailure;
    std::cout << "\nwritten: " << csv.string() << "\n";
    return kExitOk;
}

}  // namespace plimsoll::cli
