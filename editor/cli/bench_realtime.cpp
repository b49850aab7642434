// plimsoll bench --realtime: what a body costs per evaluation in the cases users run, with the
// error beside the time. Scenarios: at rest on flat water, moving (heaving, rolling, drifting)
// on flat water, moving on the buoy project's two Gerstner waves. Methods: the double-
// precision reference, the fast CPU path, each OpenCL device, the exact clip against the water
// plane (flat water only) and the per-triangle clip against each triangle's own water plane
// through its vertices' heights (Kerner 2015: what a user would pick instead on waves). Bodies:
// one, and batches of 100 and 1000 on the fast path (1 and 2 threads) and OpenCL.
//
// Errors are the largest over the timed poses of max(|dV| / V, |dF| / (rho g V),
// |dT| / (rho g V R)), F and T the pressure force and torque, against the best reference
// available: the exact clip on flat water, the reference at the largest size of the run on
// waves (the exact clip has no wave form).
#include "cli/bench_realtime.h"

#include "cli/bench.h"
#include "cli/commands.h"
#include "cli/svg_plot.h"
#include "plimsoll/bake/bake.h"
#include "plimsoll/compute/compute.h"
#include "plimsoll/compute/fast_backend.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/samples/primitives.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <vector>

namespace plimsoll::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kPoses = 24;  ///< distinct poses per scenario, cycled by the timed frames
constexpr int kRealtimeBatchSize = 64;

enum class Scenario { RestFlat, MovingFlat, MovingWaves };
const char* scenarioName(Scenario s) {
    switch (s) {
        case Scenario::RestFlat:
            return "rest, flat";
        case Scenario::MovingFlat:
            return "moving, flat";
        case Scenario::MovingWaves:
            return "moving, waves";
    }
    return "";
}

const char* scenarioKey(Scenario s) {
    switch (s) {
        case Scenario::RestFlat:
            return "rest";
        case Scenario::MovingFlat:
            return "moving";
        case Scenario::MovingWaves:
            return "waves";
    }
    return "";
}

/// Whether a filter of the command line lets `value` through (an empty filter lets all).
bool selected(const std::vector<std::string>& filter, const std::string& value,
              bool prefix = false) {
    if (filter.empty()) return true;
    return std::any_of(filter.begin(), filter.end(), [&](const std::string& f) {
        return prefix ? value.rfind(f, 0) == 0 : value == f;
    });
}

WaterModel scenarioWater(Scenario s) {
    if (s != Scenario::MovingWaves) return WaterModel::flat(0.0);
    WaterModel water;  // projects/buoy.plim.json
    water.kind = WaterModel::Kind::Gerstner;
    water.waves = {{0.12, 9.0, {1.0, 0.2}, 0.5, 0.0}, {0.05, 4.0, {0.3, 1.0}, 0.4, 1.3}};
    return water;
}

/// The body floating about half under (its centre of mass at the mean level), at rest or
/// heaving, rolling and drifting; pose k of the scenario's cycle.
BodyFrame scenarioFrame(Scenario s, const Eigen::Vector3d& centerOfMass, int k) {
    const double t = 0.1 * k;
    BodyFrame frame;
    frame.centerOfMass = centerOfMass;
    const bool moving = s != Scenario::RestFlat;
    const Eigen::Vector3d degrees =
        moving ? Eigen::Vector3d(12 * std::sin(1.3 * t), 25 * t, 8 * std::cos(0.9 * t))
               : Eigen::Vector3d(3, 0, 2);
    frame.pose = Pose::fromEulerDegrees(Eigen::Vector3d::Zero(), degrees);
    const Eigen::Vector3d center(moving ? 0.4 * t : 0.0, moving ? 0.08 * std::sin(2.1 * t) : 0.0,
                                 0.0);
    frame.pose.translation = center - frame.pose.rotation * centerOfMass;
    if (moving) {
        frame.motion.linear = {0.4, 0.17 * std::cos(2.1 * t), 0.1};
        frame.motion.angular = {0.3 * std::cos(1.3 * t), 0.44, -0.2 * std::sin(0.9 * t)};
    }
    frame.time = t;
    return frame;
}

struct Case {
    std::string mesh;
    TriangleMesh triangles;
    MassProperties exact;
    double radius = 0;
};

struct RealtimeRow {
    Scenario scenario = Scenario::RestFlat;
    std::string mesh, method;
    int size = 0;  ///< 0 for the mesh methods
    int bodies = 1;
    double usPerBody = 0;   ///< best median over the repeats, microseconds per body
    double msPerFrame = 0;  ///< all bodies
    std::optional<double> error;
};

RealtimeRow makeRow(Scenario scenario, const std::string& mesh, const std::string& method, int size,
                    int bodies) {
    RealtimeRow row;
    row.scenario = scenario;
    row.mesh = mesh;
    row.method = method;
    row.size = size;
    row.bodies = bodies;
    return row;
}

FastBackendOptions fastOn(int threads, int waveGrid = 0, int tileSize = 0) {
    FastBackendOptions options;
    options.threads = threads;
    if (waveGrid > 0) options.evaluation.waveGrid = waveGrid;
    if (tileSize > 0) options.evaluation.tileSize = static_cast<std::size_t>(tileSize);
    return options;
}

struct Answer {
    double volume = 0;
    Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
};

Answer answerOf(const BuoyancyResult& r) {
    return {r.submergedVolume, r.pressureForce, r.pressureTorque};
}

double errorOf(const std::vector<Answer>& got, const std::vector<Answer>& truth, const Case& c) {
    const double V = c.exact.volume, W = FluidSettings{}.density * FluidSettings{}.gravity * V;
    double e = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        e = std::max({e, std::abs(got[i].volume - truth[i].volume) / V,
                      (got[i].force - truth[i].force).norm() / W,
                      (got[i].torque - truth[i].torque).norm() / (W * c.radius)});
    }
    return e;
}

/// Median microseconds of `call` over `frames` calls, best of three rounds (the machine is
/// shared: the best round is the one least disturbed).
double timeCalls(int frames, const std::function<void(int)>& call) {
    for (int i = 0; i < 3; ++i) call(i);  // warm-up
    double best = 1e300;
    for (int round = 0; round < 3; ++round) {
        std::vector<double> us;
        for (int f = 0; f < frames; ++f) {
            const Clock::time_point start = Clock::now();
            call(f);
            us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
        }
        std::nth_element(us.begin(), us.begin() + us.size() / 2, us.end());
        best = std::min(best, us[us.size() / 2]);
    }
    return best;
}

/// The per-triangle wave clip: each triangle against the plane through its vertices' water
/// heights, the pressure integrated exactly over the wet part (linear depth), the torque taken
/// at each wet piece's centroid.
Answer clipPerTriangle(const TriangleMesh& mesh, const BodyFrame& frame, const WaterModel& water,
                       std::vector<Eigen::Vector3d>& world, std::vector<double>& depth) {
    const FluidSettings fluid;
    const double rhoG = fluid.density * fluid.gravity;
    const Eigen::Vector3d c = frame.pose.apply(frame.centerOfMass);
    const std::size_t n = mesh.positions.size();
    world.resize(n);
    depth.resize(3 * n);  // the vertices' x, then z, then their depths
    for (std::size_t i = 0; i < n; ++i) {
        world[i] = frame.pose.apply(mesh.positions[i]);
        depth[i] = world[i].x();
        depth[n + i] = world[i].z();
    }
    // The heights in one batched query, as the fast path takes its grid: the peer gets the
    // same vectorised water.
    water.heights(n, depth.data(), depth.data() + n, frame.time, depth.data() + 2 * n);
    for (std::size_t i = 0; i < n; ++i) depth[i] = depth[2 * n + i] - world[i].y();
    Answer a;
    auto piece = [&](const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                     const Eigen::Vector3d& p2, double d0, double d1, double d2) {
        const Eigen::Vector3d area = 0.5 * (p1 - p0).cross(p2 - p0);
        const double mean = (d0 + d1 + d2) / 3.0;
        const Eigen::Vector3d force = -rhoG * mean * area;
        a.volume -= area.y() * mean;
        a.force += force;
        a.torque += ((p0 + p1 + p2) / 3.0 - c).cross(force);
    };
    for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d p[3] = {world[t[0]], world[t[1]], world[t[2]]};
        const double d[3] = {depth[t[0]], depth[t[1]], depth[t[2]]};
        const int wet = (d[0] > 0) + (d[1] > 0) + (d[2] > 0);
        if (wet == 0) continue;
        if (wet == 3) {
            piece(p[0], p[1], p[2], d[0], d[1], d[2]);
            continue;
        }
        // Rotate so that vertex 0 is the odd one (alone wet, or alone dry), keeping the winding.
        int odd = 0;
        for (int i = 0; i < 3; ++i)
            if ((d[i] > 0) == (wet == 1)) odd = i;
        const int i1 = (odd + 1) % 3, i2 = (odd + 2) % 3;
        auto cut = [&](int u, int v) { return p[u] + (d[u] / (d[u] - d[v])) * (p[v] - p[u]); };
        const Eigen::Vector3d q1 = cut(odd, i1), q2 = cut(odd, i2);
        if (wet == 1) {
            piece(p[odd], q1, q2, d[odd], 0, 0);
        } else {
            piece(q1, p[i1], p[i2], 0, d[i1], d[i2]);
            piece(q1, p[i2], q2, 0, d[i2], 0);
        }
    }
    return a;
}

struct Method {
    std::string label;
    std::string spec;  ///< for createBuoyancyBackend
    int threads = 1;
    int waveGrid = 0;  ///< fast path only: water samples per side of its grid (0: the default)
    int tileSize = 0;  ///< fast path only: entries per tile (0: the default)
    double waveTolerance = -1;  ///< OpenCL only: OpenClOptions::waveTolerance (< 0: the default)
    OpenClWait wait = OpenClWait::automatic;  ///< OpenCL only: OpenClOptions::wait (speed alone)
    int itemsPerThread = 0;  ///< OpenCL only: OpenClOptions::itemsPerThread (0: the default)
    /// The accuracy knobs at their defaults (the wait and the items per thread may differ:
    /// speed knobs, whose rows join the 1000-body batches).
    bool defaultKnobs() const { return waveGrid == 0 && tileSize == 0 && waveTolerance < 0; }
};

/// The backend a method names: the fast path with its knobs, or createBuoyancyBackend's spec.
Result<std::unique_ptr<BuoyancyBackend>> backendFor(const Method& m,
                                                    const FastBackendOptions& fast) {
    if (m.spec.empty()) return std::unique_ptr<BuoyancyBackend>(createFastBackend(fast));
    OpenClOptions openCl;
    if (m.waveTolerance >= 0) openCl.waveTolerance = m.waveTolerance;
    openCl.wait = m.wait;
    openCl.itemsPerThread = m.itemsPerThread;
    return createBuoyancyBackend(m.spec, nullptr, openCl);
}

void printRows(const std::vector<RealtimeRow>& rows) {
    std::printf("%-14s %-7s %-22s %6s %6s %12s %12s %10s\n", "scenario", "mesh", "method", "size",
                "bodies", "us/body", "ms/frame", "error");
    for (const RealtimeRow& r : rows) {
        char error[32] = "-";
        if (r.error) std::snprintf(error, sizeof error, "%.2e", *r.error);
        const std::string size = r.size ? std::to_string(r.size) : "mesh";
        std::printf("%-14s %-7s %-22s %6s %6d %12.2f %12.4f %10s\n", scenarioName(r.scenario),
                    r.mesh.c_str(), r.method.c_str(), size.c_str(), r.bodies, r.usPerBody,
                    r.msPerFrame, error);
    }
}

bool writeCsv(const std::vector<RealtimeRow>& rows, std::ostream& out) {
    out << "scenario,mesh,method,size,bodies,us_per_body,ms_per_frame,error\n";
    for (const RealtimeRow& r : rows) {
        out << '"' << scenarioName(r.scenario) << "\"," << r.mesh << ",\"" << r.method << "\","
            << r.size << ',' << r.bodies << ',' << r.usPerBody << ',' << r.msPerFrame << ',';
        if (r.error) out << *r.error;
        out << '\n';
    }
    return bool(out);
}

/// One sentence per scenario: the fastest single-body method within each tolerance.
void printVerdicts(const std::vector<RealtimeRow>& rows) {
    for (Scenario s : {Scenario::RestFlat, Scenario::MovingFlat, Scenario::MovingWaves}) {
        for (const std::string& mesh : {std::string("sphere"), std::string("buoy")}) {
            // Only the pairs this run measured (--scenario, --bench-mesh narrow it).
            if (std::none_of(rows.begin(), rows.end(), [&](const RealtimeRow& r) {
                    return r.scenario == s && r.mesh == mesh;
                }))
                continue;
            std::string sentence = std::string(scenarioName(s)) + ", " + mesh + ":";
            for (double tolerance : {1e-2, 1e-3, 1e-4}) {
                const RealtimeRow* best = nullptr;
                for (const RealtimeRow& r : rows)
                    if (r.scenario == s && r.mesh == mesh && r.bodies == 1 && r.error &&
                        *r.error <= tolerance && (!best || r.usPerBody < best->usPerBody))
                        best = &r;
                char part[160];
                if (best)
                    std::snprintf(
                        part, sizeof part, " within %.0e the %s%s wins (%.1f us);", tolerance,
                        best->method.c_str(),
                        best->size ? (" at " + std::to_string(best->size) + "^2").c_str() : "",
                        best->usPerBody);
                else
                    std::snprintf(part, sizeof part, " nothing measured reaches %.0e;", tolerance);
                sentence += part;
            }
            std::cout << sentence << "\n";
        }
    }
}

/// The methods the bench compares: the reference, the fast path and its knobs, and each
/// OpenCL device with its knobs.
std::vector<Method> realtimeMethods() {
    std::vector<Method> methods = {{"reference", "reference", 1}, {"fast CPU", "", 1}};
    // The fast path's accuracy knob on waves: how many water samples per side of its grid over
    // the body (the default, 9, is the "fast CPU" row).
    for (int grid : {5, 7, 13})
        methods.push_back({"fast CPU (wave grid " + std::to_string(grid) + ")", "", 1, grid});
    // And the size of its tiles (the default, 32, is the "fast CPU" row): a speed knob, the
    // closed forms being exact on flat water.
    for (int tile : {16, 64})
        methods.push_back({"fast CPU (tiles " + std::to_string(tile) + ")", "", 1, 0, tile});
    for (const ComputeDevice& d : listComputeDevices()) {
        const std::string label = "OpenCL " + std::to_string(d.index) + (d.isGpu ? " GPU" : " CPU");
        methods.push_back({label, std::to_string(d.index), 1});
        // Its accuracy knob on waves (the default, OpenClOptions::waveTolerance, is the plain
        // row): 0 sums every tile at the waterline entry by entry.
        for (double tolerance : {0.0, 1e-2}) {
            char name[64];
            std::snprintf(name, sizeof name, "%s (wave tol %g)", label.c_str(), tolerance);
            methods.push_back({name, std::to_string(d.index), 1, 0, 0, tolerance});
        }
        // Its speed knob: how the host waits for the totals (the default blocks; this row
        // polls the read's event instead).
        Method spinWait{label + " (spin wait)", std::to_string(d.index), 1};
        spinWait.wait = OpenClWait::spin;
        methods.push_back(spinWait);
        // And the tile size on a GPU (the default, 8 entries a work-item, is the plain row):
        // a lone body's tiles fill a few of a GPU's groups, so a shorter chain per work-item
        // may pay for more tiles. Not on CPU devices: PoCL pays per group (docs/design.md).
        if (d.isGpu) {
            for (int items : {1, 2, 4, 16, 32}) {
                Method smaller{label + " (items " + std::to_string(items) + ")",
                               std::to_string(d.index), 1};
                smaller.itemsPerThread = items;
                methods.push_back(smaller);
            }
        }
    }
    return methods;
}

/// The meshes the bench evaluates (those `o.meshes` selects), with their exact mass
/// properties and radius.
std::vector<Case> realtimeCases(const RealtimeBenchOptions& o) {
    std::vector<Case> cases;
    for (auto [name, mesh] : {std::pair{std::string("sphere"), makeUvSphere(0.5, 64, 32)},
                              std::pair{std::string("buoy"), makeBuoy()}}) {
        if (!selected(o.meshes, name)) continue;
        Case c;
        c.mesh = name;
        c.exact = exactSolidMassProperties(mesh, 1.0);
        for (const auto& p : mesh.positions)
            c.radius = std::max(c.radius, (p - c.exact.centerOfMass).norm());
        c.triangles = std::move(mesh);
        cases.push_back(std::move(c));
    }
    return cases;
}

/// Writes realtime.csv and realtime.svg (error against time per body) into `o.out`.
int writeRealtimeOutputs(const RealtimeBenchOptions& o, const std::vector<RealtimeRow>& rows) {
    auto fail = [](const Error& e) {
        std::cerr << "error: " << e.message << "\n";
        return kExitFailure;
    };
    if (!createOutputFolder(o.out)) return kExitFailure;
    const fs::path csv = fs::path(o.out) / "realtime.csv", svg = fs::path(o.out) / "realtime.svg";
    if (Status st =
            writeFileAtomically(csv, [&](std::ostream& out) { return writeCsv(rows, out); });
        !st.ok())
        return fail(st.error());
    LogLogPlot plot;
    plot.title = "Plimsoll: error against time per body (one body)";
    plot.xLabel = "time per evaluation (us)";
    plot.yLabel = "largest error (volume, force, torque; relative)";
    for (const RealtimeRow& r : rows) {
        if (r.bodies != 1 || !r.error) continue;
        const std::string name =
            std::string(scenarioName(r.scenario)) + ", " + r.mesh + ", " + r.method;
        auto series = std::find_if(plot.series.begin(), plot.series.end(),
                                   [&](const PlotSeries& p) { return p.name == name; });
        if (series == plot.series.end()) series = plot.series.insert(series, {name, {}});
        series->points.push_back(
            {r.usPerBody, std::max(*r.error, 1e-12), r.size ? std::to_string(r.size) : "mesh"});
    }
    if (Status st =
            writeFileAtomically(svg, [&](std::ostream& out) { return writeSvg(plot, out); });
        !st.ok())
        return fail(st.error());
    std::cout << "\nwritten: " << csv.string() << ", " << svg.string() << "\n";
    return kExitOk;
}

/// One run of the real-time table: each case's bakes, and per scenario the rows of the mesh
/// clips, of every method at every size, and of the batches.
class RealtimeRun {
public:
    explicit RealtimeRun(const RealtimeBenchOptions& o)
        : o_(o),
          frames_(o.frames > 0 ? o.frames
                  : o.quick    ? 30
                               : 200),
          allSizes_(o.quick ? std::vector<int>{32, 64, 128}
                            : std::vector<int>{32, 64, 128, 256, 512, 1024, 2048}),
          sizes_(o.sizes.empty() ? allSizes_ : o.sizes),
          methods_(realtimeMethods()) {
        // The waves' truth: the reference at the largest size of the unfiltered run, so that a
        // narrowed run reports the same errors.
        for (int size : allSizes_)
            if (size <= kReferenceMaxSize) truthSize_ = std::max(truthSize_, size);
    }

    int frames() const { return frames_; }
    const std::vector<RealtimeRow>& rows() const { return rows_; }

    Status runCase(const Case& c) {
        baked_.clear();
        std::vector<int> bakedSizes = sizes_;
        bakedSizes.push_back(truthSize_);
        bakedSizes.push_back(kRealtimeBatchSize);
        for (int size : bakedSizes) {
            if (baked_.count(size)) continue;
            BakeSettings settings;
            settings.size = size;
            Result<SurfaceTextures> t = bakeSurfaceTextures(c.triangles, settings);
            if (!t) return t.error();
            baked_[size] = std::move(*t);
        }
        for (Scenario s : {Scenario::RestFlat, Scenario::MovingFlat, Scenario::MovingWaves}) {
            if (!selected(o_.scenarios, scenarioKey(s))) continue;
            if (Status st = runScenario(c, s); !st.ok()) return st;
        }
        return Ok{};
    }

private:
    bool bodiesSelected(int n) const {
        return o_.bodies.empty() ||
               std::find(o_.bodies.begin(), o_.bodies.end(), n) != o_.bodies.end();
    }

    Status runScenario(const Case& c, Scenario s) {
        const WaterModel water = scenarioWater(s);
        std::vector<BodyFrame> poses;
        for (int k = 0; k < kPoses; ++k) poses.push_back(scenarioFrame(s, c.exact.centerOfMass, k));
        // The truth for the errors (see the file comment).
        std::vector<Answer> truth;
        for (const BodyFrame& f : poses) {
            if (s == Scenario::MovingWaves) {
                truth.push_back(
                    answerOf(evaluateBuoyancyReference(baked_[truthSize_], f, water, {})));
            } else {
                truth.push_back(answerOf(evaluateBuoyancyExact(c.triangles, f, 0.0, {})));
            }
        }
        if (s != Scenario::MovingWaves)
            meshRow(c, s, poses, truth, "exact plane clip", [&](const BodyFrame& f) {
                return answerOf(evaluateBuoyancyExact(c.triangles, f, 0.0, {}));
            });
        meshRow(c, s, poses, truth, "per-triangle wave clip", [&](const BodyFrame& f) {
            return clipPerTriangle(c.triangles, f, water, worldScratch_, depthScratch_);
        });
        for (const Method& m : methods_) {
            if (!bodiesSelected(1) || !selected(o_.methods, m.label, true)) continue;
            // Flat water has no grid, and no wave tolerance.
            if ((m.waveGrid > 0 || m.waveTolerance >= 0) && s != Scenario::MovingWaves) continue;
            for (int size : sizes_) {
                if (m.spec == "reference" && size > kReferenceMaxSize) continue;
                if (Status st = backendRow(c, s, water, poses, truth, m, size); !st.ok()) return st;
            }
        }
        // Batches: the sphere only, at one size, on the fast path (1 and 2 threads) and OpenCL.
        if (c.mesh != "sphere") return Ok{};
        for (int bodies : {100, 1000}) {
            if (!bodiesSelected(bodies)) continue;
            std::vector<Method> batchMethods = {{"fast CPU, 1 thread", "", 1},
                                                {"fast CPU, 2 threads", "", 2}};
            for (const Method& m : methods_)
                if (m.label.rfind("OpenCL", 0) == 0 && m.defaultKnobs()) batchMethods.push_back(m);
            for (const Method& m : batchMethods) {
                if (!selected(o_.methods, m.label, true)) continue;
                if (Status st = batchRow(c, s, water, poses, m, bodies); !st.ok()) return st;
            }
        }
        return Ok{};
    }

    /// A method that works on the mesh itself (no bake): its error and time per evaluation.
    void meshRow(const Case& c, Scenario s, const std::vector<BodyFrame>& poses,
                 const std::vector<Answer>& truth, const std::string& method,
                 const std::function<Answer(const BodyFrame&)>& run) {
        if (!bodiesSelected(1) || !selected(o_.methods, method, true)) return;
        RealtimeRow row = makeRow(s, c.mesh, method, 0, 1);
        std::vector<Answer> got;
        for (const BodyFrame& f : poses) got.push_back(run(f));
        row.error = errorOf(got, truth, c);
        row.usPerBody = timeCalls(frames_, [&](int f) { run(poses[f % kPoses]); });
        row.msPerFrame = row.usPerBody * 1e-3;
        std::cerr << "bench: " << scenarioName(s) << " " << c.mesh << " " << method << ": "
                  << row.usPerBody << " us\n";
        rows_.push_back(row);
    }

    /// A backend on one body at one size: its error and time per evaluation, and where its time
    /// goes (tiles).
    Status backendRow(const Case& c, Scenario s, const WaterModel& water,
                      const std::vector<BodyFrame>& poses, const std::vector<Answer>& truth,
                      const Method& m, int size) {
        Result<std::unique_ptr<BuoyancyBackend>> made =
            backendFor(m, fastOn(1, m.waveGrid, m.tileSize));
        if (!made) return made.error();
        BuoyancyBackend& backend = **made;
        const std::size_t id = backend.addBody(baked_[size], c.exact.centerOfMass);
        std::vector<Answer> got;
        BuoyancyResult result;
        Status status = Ok{};
        auto run = [&](const BodyFrame& f) {
            BodyRequest request;
            request.body = id;
            request.frame = f;
            status = backend.evaluate({&request, 1}, water, {&result, 1});
            return answerOf(result);
        };
        for (const BodyFrame& f : poses) got.push_back(run(f));
        if (!status.ok()) return status.error();
        RealtimeRow row = makeRow(s, c.mesh, m.label, size, 1);
        row.error = errorOf(got, truth, c);
        row.usPerBody = timeCalls(frames_, [&](int f) { run(poses[f % kPoses]); });
        row.msPerFrame = row.usPerBody * 1e-3;
        std::cerr << "bench: " << scenarioName(s) << " " << c.mesh << " " << m.label << " " << size
                  << "^2: " << row.usPerBody << " us";
        if (const TileCounts counts = backend.lastTileCounts(); counts.tiles > 0) {
            // Where the device's time goes: its tiles at the last pose.
            std::cerr << " (tiles " << counts.tiles << ": dry " << counts.dry << ", closed form "
                      << counts.closedForm << " (drag too " << counts.dragClosedForm
                      << "), per entry " << counts.perEntry() << ")";
        }
        if (m.spec.empty() && m.defaultKnobs()) {
            // Where the fast path's time goes: its tiles at the first pose.
            plimsoll_eval::FastScratch scratch;
            plimsoll_eval::FastStats stats;
            evaluateBuoyancyFast(makeFastBody(baked_[size], c.exact.centerOfMass), poses[0], water,
                                 {}, scratch, &stats);
            std::cerr << " (nodes dry " << stats.dry << ", closed form " << stats.closedForm
                      << ", per entry " << stats.perEntry << ", drag per entry "
                      << stats.dragPerEntry << "; water samples " << stats.waterSamples
                      << ", water velocities " << stats.velocitySamples << ")";
        }
        std::cerr << "\n";
        rows_.push_back(row);
        return Ok{};
    }

    /// A batch of `bodies` spheres spread over the water, one evaluate call per frame.
    Status batchRow(const Case& c, Scenario s, const WaterModel& water,
                    const std::vector<BodyFrame>& poses, const Method& m, int bodies) {
        Result<std::unique_ptr<BuoyancyBackend>> made = backendFor(m, fastOn(m.threads));
        if (!made) return made.error();
        BuoyancyBackend& backend = **made;
        std::vector<BodyRequest> requests(bodies);
        for (int b = 0; b < bodies; ++b) {
            requests[b].body = backend.addBody(baked_[kRealtimeBatchSize], c.exact.centerOfMass);
            requests[b].frame = poses[b % kPoses];
            // Spread out (the same water everywhere on flat water; other waves on waves).
            requests[b].frame.pose.translation.x() += 3.0 * (b % 32);
            requests[b].frame.pose.translation.z() += 3.0 * (b / 32);
        }
        std::vector<BuoyancyResult> results(bodies);
        Status status = Ok{};
        const double us = timeCalls(std::max(5, frames_ / 10), [&](int) {
            status = backend.evaluate(requests, water, results);
        });
        if (!status.ok()) return status.error();
        RealtimeRow row = makeRow(s, c.mesh, m.label, kRealtimeBatchSize, bodies);
        row.msPerFrame = us * 1e-3;
        row.usPerBody = us / bodies;
        std::cerr << "bench: " << scenarioName(s) << " " << bodies << " x " << m.label << ": "
                  << row.msPerFrame << " ms/frame\n";
        rows_.push_back(row);
        return Ok{};
    }

    const RealtimeBenchOptions& o_;
    const int frames_;
    const std::vector<int> allSizes_, sizes_;
    const std::vector<Method> methods_;
    int truthSize_ = 0;
    std::map<int, SurfaceTextures> baked_;  ///< the case's bakes, by size
    std::vector<RealtimeRow> rows_;
    std::vector<Eigen::Vector3d> worldScratch_;
    std::vector<double> depthScratch_;
};

}  // namespace

int runRealtimeBench(const RealtimeBenchOptions& o) {
    RealtimeRun run(o);
    for (const Case& c : realtimeCases(o)) {
        if (Status st = run.runCase(c); !st.ok()) {
            std::cerr << "error: " << st.error().message << "\n";
            return kExitFailure;
        }
    }
    std::cout
        << "Per evaluation, best of 3 rounds of the median of " << run.frames()
        << " calls; errors against the exact clip (flat) or the reference at the largest size "
           "(waves); machine shared with other work.\n\n";
    printRows(run.rows());
    std::cout << "\n";
    printVerdicts(run.rows());

    return writeRealtimeOutputs(o, run.rows());
}

}  // namespace plimsoll::cli
