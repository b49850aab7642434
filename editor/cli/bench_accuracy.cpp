// plimsoll bench [--sizes 32,64,...] [--frames F] [--out DIR] [--mesh MESH] [--quick]: the speed
// against accuracy trade of the texture method. For every texture size and compute device: the
// time per frame of one body, and its largest error against the exact clip over a sweep of
// depths and orientations; the exact method's own time per mesh; a batch of 1000 bodies. A
// table on stdout, DIR/bench.csv, and DIR/bench.svg (error against time per frame, log-log).
#include "cli/bench.h"

#include "cli/commands.h"
#include "cli/common.h"
#include "cli/svg_plot.h"
#include "plimsoll/bake/bake.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/compute/compute.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/io/mesh_io.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/project/project.h"
#include "plimsoll/scene/scene.h"
#include "plimsoll/scene/world.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

namespace plimsoll::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kWarmupFrames = 5;
constexpr int kSweepLevels = 21;
constexpr int kBatchBodies = 1000;
constexpr int kAccuracyBatchSize = 128;
/// What a frame reads per entry: float4 position + float4 area vector.
constexpr double kBytesPerEntry = 32;
constexpr std::size_t kMiB = std::size_t{1} << 20;

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// A pose of the accuracy sweep: the body rotated about its origin, the water plane at `level`.
struct SweepPose {
    Pose pose;
    double level = 0;
};

struct BenchMesh {
    std::string name;
    TriangleMesh mesh;
    MassProperties exact;  ///< density 1: volume and centre of mass of the closed mesh
    double diagonal = 0;   ///< bounding-box diagonal, m
    std::vector<SweepPose> sweep;
};

/// Three orientations (the paper's figure 9 case and two tilts), each with water levels from
/// the lowest to the highest vertex of the posed body: dry to fully submerged, whatever the
/// mesh's size and origin.
std::vector<SweepPose> makeSweep(const TriangleMesh& mesh) {
    const Eigen::Vector3d orientations[] = {{0, 0, 0}, {30, 0, 0}, {20, 40, 60}};
    std::vector<SweepPose> sweep;
    for (const Eigen::Vector3d& degrees : orientations) {
        const Pose pose = Pose::fromEulerDegrees(Eigen::Vector3d::Zero(), degrees);
        double low = 1e300, high = -1e300;
        for (const Eigen::Vector3d& p : mesh.positions) {
            low = std::min(low, pose.apply(p).y());
            high = std::max(high, pose.apply(p).y());
        }
        for (int i = 0; i < kSweepLevels; ++i)
            sweep.push_back({pose, low + (high - low) * i / (kSweepLevels - 1)});
    }
    return sweep;
}

BenchMesh makeBenchMesh(std::string name, TriangleMesh mesh) {
    BenchMesh m;
    m.name = std::move(name);
    m.exact = exactSolidMassProperties(mesh, 1.0);
    m.diagonal = computeBounds(mesh).diagonal();
    m.sweep = makeSweep(mesh);
    m.mesh = std::move(mesh);
    return m;
}

/// One texture size of one mesh with what every device's row is held against: the exact
/// results about the textures' own centre of mass, so both methods share the torque's point.
struct Baked {
    int size = 0;
    SurfaceTextures textures;
    double bakeMs = 0;
    Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();
    double boundingRadius = 0;          ///< farthest vertex from centerOfMass, m
    std::vector<BuoyancyResult> exact;  ///< one per sweep pose
};

Result<Baked> bake(const BenchMesh& m, int size) {
    BakeSettings settings;
    settings.size = size;
    const Clock::time_point start = Clock::now();
    Result<SurfaceTextures> textures = bakeSurfaceTextures(m.mesh, settings);
    if (!textures) return textures.error();
    Baked b;
    b.bakeMs = msSince(start);
    b.size = size;
    b.textures = std::move(*textures);
    b.centerOfMass = textureSolidMassProperties(b.textures, 1.0).centerOfMass;
    for (const Eigen::Vector3d& p : m.mesh.positions)
        b.boundingRadius = std::max(b.boundingRadius, (p - b.centerOfMass).norm());
    for (const SweepPose& s : m.sweep) {
        BodyFrame frame;
        frame.pose = s.pose;
        frame.centerOfMass = b.centerOfMass;
        b.exact.push_back(evaluateBuoyancyExact(m.mesh, frame, s.level, FluidSettings{}));
    }
    return b;
}

struct Device {
    std::string label;  ///< short, for the table: "cl0 CPU", "reference"
    std::string spec;   ///< for createBuoyancyBackend
    std::string name;   ///< device and platform
    bool isGpu = false;
    std::optional<double> bandwidthGBs;  ///< measured copy bandwidth (OpenCL devices)

    bool isReference() const { return spec == "reference"; }
};

struct Spread {
    double median = 0, p10 = 0, p90 = 0;
};

double quantile(std::vector<double> values, double q) {
    std::sort(values.begin(), values.end());
    const double at = q * static_cast<double>(values.size() - 1);
    const std::size_t below = static_cast<std::size_t>(at);
    const std::size_t above = std::min(below + 1, values.size() - 1);
    return values[below] + (at - static_cast<double>(below)) * (values[above] - values[below]);
}

Spread spreadOf(const std::vector<double>& values) {
    return {quantile(values, 0.5), quantile(values, 0.1), quantile(values, 0.9)};
}

/// Largest errors over the sweep, each relative to a scale of the body so meshes compare.
struct Errors {
    double volume = 0;            ///< |dV_s| / V
    double centerOfBuoyancy = 0;  ///< |dC_B| / bounding-box diagonal, where V_s > 1% of V
    double torque = 0;            ///< |dT| / (rho g V R), R the bounding radius

    double largest() const { return std::max({volume, centerOfBuoyancy, torque}); }
};

Errors compareToExact(const std::vector<BuoyancyResult>& results, const BenchMesh& m,
                      const Baked& b) {
    const FluidSettings fluid;
    const double volume = m.exact.volume;
    const double torqueScale = fluid.density * fluid.gravity * volume * b.boundingRadius;
    Errors e;
    for (std::size_t i = 0; i < results.size(); ++i) {
        const BuoyancyResult& r = results[i];
        const BuoyancyResult& x = b.exact[i];
        e.volume = std::max(e.volume, std::abs(r.submergedVolume - x.submergedVolume) / volume);
        // Below 1% of V the centre of a sliver is ill-conditioned and says nothing of the method.
        if (x.submergedVolume > 0.01 * volume) {
            e.centerOfBuoyancy = std::max(
                e.centerOfBuoyancy, (r.centerOfBuoyancy - x.centerOfBuoyancy).norm() / m.diagonal);
        }
        e.torque = std::max(e.torque, (r.torque - x.torque).norm() / torqueScale);
    }
    return e;
}

enum class RowKind { Texture, Exact, Batch };

struct AccuracyRow {
    RowKind kind = RowKind::Texture;
    std::string mesh;
    std::string device;  ///< Device::label, or "exact (C++)"
    std::string deviceName;
    int size = 0;  ///< texels per side; 0 for the exact method
    int bodies = 1;
    std::size_t entries = 0;  ///< texel entries per frame, all bodies together
    std::optional<double> bakeMs;
    Spread frame;                                ///< ms per frame (evaluate's wall clock)
    std::optional<double> kernelMs, transferMs;  ///< medians, from the device's profiling events
    std::optional<double> reduceMs;              ///< of kernelMs, the per-body sums (median)
    std::optional<double> bandwidthShare;        ///< of the measured copy bandwidth
    std::optional<Errors> errors;
};

AccuracyRow textureRow(RowKind kind, const BenchMesh& m, const Baked& b, const Device& device) {
    AccuracyRow row;
    row.kind = kind;
    row.mesh = m.name;
    row.device = device.label;
    row.deviceName = device.name;
    row.size = b.size;
    row.entries = b.textures.coveredCount();
    row.bakeMs = b.bakeMs;
    return row;
}

using FrameFunction = std::function<Result<FrameTimings>(int frame)>;

/// Runs kWarmupFrames + frames frames and fills the row's timings from all but the warm-up.
Status timeFrames(int frames, const FrameFunction& run, const Device* device, AccuracyRow& row) {
    std::vector<double> total, kernel, reduce, transfer;
    for (int f = 0; f < kWarmupFrames + frames; ++f) {
        Result<FrameTimings> t = run(f);
        if (!t) return t.error();
        if (f < kWarmupFrames) continue;
        total.push_back(t->totalMs);
        kernel.push_back(t->kernelMs);
        reduce.push_back(t->reduceMs);
        transfer.push_back(t->uploadMs + t->readbackMs);
    }
    row.frame = spreadOf(total);
    // Only OpenCL devices report where the time went; the reference knows only the total.
    if (device && !device->isReference()) {
        row.kernelMs = quantile(kernel, 0.5);
        row.reduceMs = quantile(reduce, 0.5);
        row.transferMs = quantile(transfer, 0.5);
        if (device->bandwidthGBs && *row.kernelMs > 0) {
            const double gbPerS =
                static_cast<double>(row.entries) * kBytesPerEntry / (*row.kernelMs * 1e-3) / 1e9;
            row.bandwidthShare = gbPerS / *device->bandwidthGBs;
        }
    }
    return Ok{};
}

BodyRequest requestFor(std::size_t body, const Pose& pose) {
    BodyRequest request;
    request.body = body;
    request.frame.pose = pose;
    return request;
}

/// The sweep reports where a device's frame goes (kernel_ms, reduce_ms, transfer_ms), from
/// profiling events; plimsoll bench --realtime times the frames without them.
const OpenClOptions kTimedDevice{.deviceTimings = true};

/// One body on one device: the accuracy sweep, then the timed frames cycling through it.
Result<AccuracyRow> measureTexture(const BenchMesh& m, const Baked& b, const Device& device,
                                   int frames) {
    Result<std::unique_ptr<BuoyancyBackend>> created =
        createBuoyancyBackend(device.spec, nullptr, kTimedDevice);
    if (!created) return created.error();
    BuoyancyBackend& backend = **created;
    const std::size_t body = backend.addBody(b.textures, b.centerOfMass);
    auto evaluatePose = [&](const SweepPose& s, BuoyancyResult& result) {
        const BodyRequest request = requestFor(body, s.pose);
        return backend.evaluate({&request, 1}, WaterModel::flat(s.level), {&result, 1});
    };

    AccuracyRow row = textureRow(RowKind::Texture, m, b, device);
    std::vector<BuoyancyResult> results(m.sweep.size());
    for (std::size_t i = 0; i < m.sweep.size(); ++i)
        if (Status s = evaluatePose(m.sweep[i], results[i]); !s.ok()) return s.error();
    row.errors = compareToExact(results, m, b);

    const FrameFunction run = [&](int f) -> Result<FrameTimings> {
        BuoyancyResult result;
        if (Status s = evaluatePose(m.sweep[f % m.sweep.size()], result); !s.ok()) return s.error();
        return backend.lastTimings();
    };
    if (Status s = timeFrames(frames, run, &device, row); !s.ok()) return s.error();
    return row;
}

/// The exact clip on the same poses: the baseline the textures have to beat.
AccuracyRow measureExact(const BenchMesh& m, int frames) {
    AccuracyRow row;
    row.kind = RowKind::Exact;
    row.mesh = m.name;
    row.device = "exact (C++)";
    row.deviceName = "exact clip, C++";
    const FrameFunction run = [&](int f) -> Result<FrameTimings> {
        const SweepPose& s = m.sweep[f % m.sweep.size()];
        BodyFrame frame;
        frame.pose = s.pose;
        frame.centerOfMass = m.exact.centerOfMass;
        const Clock::time_point start = Clock::now();
        evaluateBuoyancyExact(m.mesh, frame, s.level, FluidSettings{});
        return FrameTimings{.totalMs = msSince(start)};
    };
    // The run cannot fail: it only times evaluateBuoyancyExact.
    (void)timeFrames(frames, run, nullptr, row);
    return row;
}

/// kBatchBodies copies of one body in one evaluate per frame, each at its own pose of the
/// sweep (the water level moved into the pose, as all bodies share one water).
Result<AccuracyRow> measureBatch(const BenchMesh& m, const Baked& b, const Device& device,
                                 int frames) {
    Result<std::unique_ptr<BuoyancyBackend>> created =
        createBuoyancyBackend(device.spec, nullptr, kTimedDevice);
    if (!created) return created.error();
    BuoyancyBackend& backend = **created;
    for (int i = 0; i < kBatchBodies; ++i) backend.addBody(b.textures, b.centerOfMass);

    AccuracyRow row = textureRow(RowKind::Batch, m, b, device);
    row.bodies = kBatchBodies;
    row.entries *= kBatchBodies;
    std::vector<BodyRequest> requests(kBatchBodies);
    std::vector<BuoyancyResult> results(kBatchBodies);
    const WaterModel water = WaterModel::flat(0.0);
    const FrameFunction run = [&](int f) -> Result<FrameTimings> {
        for (int i = 0; i < kBatchBodies; ++i) {
            const SweepPose& s = m.sweep[(i + f) % m.sweep.size()];
            requests[i] = requestFor(i, s.pose);
            requests[i].frame.pose.translation.y() -= s.level;
        }
        if (Status s = backend.evaluate(requests, water, results); !s.ok()) return s.error();
        return backend.lastTimings();
    };
    if (Status s = timeFrames(frames, run, &device, row); !s.ok()) return s.error();
    return row;
}

std::vector<Device> findDevices(bool quick) {
    std::vector<Device> devices;
    for (const ComputeDevice& d : listComputeDevices()) {
        Device device;
        device.label = "cl" + std::to_string(d.index) + (d.isGpu ? " GPU" : " CPU");
        device.spec = std::to_string(d.index);
        device.name = d.name + " (" + d.platform + ")";
        device.isGpu = d.isGpu;
        // Buffers far beyond the caches: the bandwidth a frame of large textures can reach.
        Result<double> bandwidth = measureCopyBandwidth(device.spec, (quick ? 64 : 256) * kMiB);
        if (bandwidth) {
            device.bandwidthGBs = *bandwidth;
        } else {
            std::cerr << "bench: no bandwidth for " << device.label << ": "
                      << bandwidth.error().message << "\n";
        }
        devices.push_back(std::move(device));
    }
    Device reference;
    reference.label = reference.spec = "reference";
    reference.name = "reference (C++)";
    devices.push_back(std::move(reference));
    return devices;
}

// --- Output ---------------------------------------------------------------------------------

// Beside bench.h's format of a double, not in place of it (both must be found here).
using cli::format;

std::string format(const char* spec, const std::optional<double>& value) {
    return value ? format(spec, *value) : "-";
}

const char* kindName(RowKind kind) {
    switch (kind) {
        case RowKind::Texture:
            return "texture";
        case RowKind::Exact:
            return "exact";
        case RowKind::Batch:
            return "batch";
    }
    return "";
}

std::string sizeCell(const AccuracyRow& r) {
    if (r.kind == RowKind::Exact) return "-";
    const std::string n = std::to_string(r.size);
    return r.kind == RowKind::Batch ? std::to_string(r.bodies) + "x" + n : n;
}

std::vector<std::string> tableCells(const AccuracyRow& r) {
    std::optional<double> percent;
    if (r.bandwidthShare) percent = 100.0 * *r.bandwidthShare;
    const std::optional<Errors>& e = r.errors;
    return {r.mesh,
            r.device,
            sizeCell(r),
            r.kind == RowKind::Exact ? "-" : std::to_string(r.entries),
            format("%.1f", r.bakeMs),
            format("%.4g", r.frame.median),
            format("%.4g", r.frame.p10),
            format("%.4g", r.frame.p90),
            format("%.4g", r.kernelMs),
            format("%.4g", r.reduceMs),
            format("%.4g", r.transferMs),
            format("%.1f", percent),
            e ? format("%.2e", e->volume) : "-",
            e ? format("%.2e", e->centerOfBuoyancy) : "-",
            e ? format("%.2e", e->torque) : "-"};
}

void printTable(const std::vector<AccuracyRow>& rows) {
    const std::vector<std::string> header = {"mesh",      "device",        "N",           "entries",
                                             "bake ms",   "frame ms",      "p10 ms",      "p90 ms",
                                             "kernel ms", "of which sums", "transfer ms", "% bw",
                                             "vol err",   "cob err",       "torque err"};
    std::vector<std::vector<std::string>> lines = {header};
    for (const AccuracyRow& r : rows) lines.push_back(tableCells(r));
    printAligned(lines, 2);
}

std::string csvField(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

std::string csvNumber(const char* spec, const std::optional<double>& value) {
    return value ? format(spec, *value) : "";
}

bool writeCsv(const std::vector<AccuracyRow>& rows, std::ostream& out) {
    out << "kind,mesh,device,device_name,size,bodies,entries,bake_ms,frame_median_ms,"
           "frame_p10_ms,frame_p90_ms,kernel_ms,reduce_ms,transfer_ms,bandwidth_fraction,volume_"
           "error,"
           "cob_error,torque_error\n";
    for (const AccuracyRow& r : rows) {
        const std::optional<Errors>& e = r.errors;
        const auto error = [&](double Errors::*field) {
            return e ? format("%.6e", (*e).*field) : std::string();
        };
        out << kindName(r.kind) << ',' << csvField(r.mesh) << ',' << csvField(r.device) << ','
            << csvField(r.deviceName) << ','
            << (r.kind == RowKind::Exact ? "" : std::to_string(r.size)) << ',' << r.bodies << ','
            << (r.kind == RowKind::Exact ? "" : std::to_string(r.entries)) << ','
            << csvNumber("%.6g", r.bakeMs) << ',' << format("%.6g", r.frame.median) << ','
            << format("%.6g", r.frame.p10) << ',' << format("%.6g", r.frame.p90) << ','
            << csvNumber("%.6g", r.kernelMs) << ',' << csvNumber("%.6g", r.reduceMs) << ','
            << csvNumber("%.6g", r.transferMs) << ',' << csvNumber("%.6g", r.bandwidthShare) << ','
            << error(&Errors::volume) << ',' << error(&Errors::centerOfBuoyancy) << ','
            << error(&Errors::torque) << '\n';
    }
    return static_cast<bool>(out);
}

/// Error against time, one line per mesh and device through its texture sizes, the exact
/// method as a vertical line per mesh: where a line runs left of it, textures pay off.
LogLogPlot makePlot(const std::vector<AccuracyRow>& rows) {
    LogLogPlot plot;
    plot.title = "Plimsoll: accuracy against time per frame (one body)";
    plot.xLabel = "time per frame, median (ms)";
    plot.yLabel = "largest error over the sweep (volume, CoB, torque; relative)";
    for (const AccuracyRow& r : rows) {
        if (r.kind == RowKind::Exact) {
            plot.markers.push_back({r.frame.median, "exact " + r.mesh});
            continue;
        }
        if (r.kind != RowKind::Texture) continue;
        const std::string name = r.mesh + ", " + r.device;
        auto series = std::find_if(plot.series.begin(), plot.series.end(),
                                   [&](const PlotSeries& s) { return s.name == name; });
        if (series == plot.series.end()) series = plot.series.insert(series, {name, {}});
        series->points.push_back({r.frame.median, r.errors->largest(), std::to_string(r.size)});
    }
    return plot;
}

void reportRow(const AccuracyRow& r) {
    const std::vector<std::string> c = tableCells(r);
    std::cerr << "bench: " << r.mesh << " " << r.device
              << (r.kind == RowKind::Exact ? "" : " N=" + c[2]) << ": " << c[5] << " ms/frame";
    if (r.errors) std::cerr << ", errors vol " << c[11] << " cob " << c[12] << " torque " << c[13];
    std::cerr << "\n";
}

// --- The run --------------------------------------------------------------------------------

}  // namespace

int runAccuracyBench(const BenchOptions& o) {
    const int frames = o.frames > 0 ? o.frames : o.quick ? 10 : 50;
    std::vector<Device> devices = findDevices(o.quick);
    std::vector<int> sizes = o.sizes;
    if (!o.sizesGiven) {
        sizes = o.quick ? std::vector<int>{32, 64, 128, 256}
                        : std::vector<int>{32, 64, 128, 256, 512, 1024, 2048};
        if (!o.quick &&
            std::any_of(devices.begin(), devices.end(), [](const Device& d) { return d.isGpu; }))
            sizes.push_back(4096);
    }

    std::vector<BenchMesh> meshes;
    meshes.push_back(makeBenchMesh("sphere", makeUvSphere(0.5, 64, 32)));
    if (!fs::exists(o.mesh)) {
        std::cerr << "bench: " << o.mesh << " not found: benchmarking the sphere only\n";
    } else {
        // Packed for the middle of the sizes (gutters are whole texels there).
        BakeOptions atlas;
        atlas.size = 256;
        std::optional<BakeableMesh> mesh = loadMeshForBake(o.mesh, atlas);
        if (!mesh) return kExitFailure;
        meshes.push_back(makeBenchMesh(fs::path(o.mesh).stem().string(), std::move(mesh->mesh)));
    }

    auto fail = [](const Error& error) {
        std::cerr << "error: " << error.message << "\n";
        return kExitFailure;
    };
    std::vector<AccuracyRow> rows;
    for (const BenchMesh& m : meshes) {
        std::vector<Baked> bakes;
        for (int size : sizes) {
            Result<Baked> baked = bake(m, size);
            if (!baked) return fail(baked.error());
            std::cerr << "bench: baked " << m.name << " " << size << "^2 in "
                      << format("%.1f", baked->bakeMs) << " ms, " << baked->textures.coveredCount()
                      << " entries\n";
            bakes.push_back(std::move(*baked));
        }
        for (const Device& device : devices) {
            for (const Baked& b : bakes) {
                if (device.isReference() && b.size > kReferenceMaxSize) continue;
                Result<AccuracyRow> row = measureTexture(m, b, device, frames);
                if (!row) return fail(row.error());
                reportRow(*row);
                rows.push_back(std::move(*row));
            }
        }
        rows.push_back(measureExact(m, frames));
        reportRow(rows.back());
    }
    // The batch is the kernels' case: the reference would take seconds a frame to say so.
    Result<Baked> batchBake = bake(meshes.front(), kAccuracyBatchSize);
    if (!batchBake) return fail(batchBake.error());
    for (const Device& device : devices) {
        if (device.isReference()) continue;
        Result<AccuracyRow> row = measureBatch(meshes.front(), *batchBake, device, frames);
        if (!row) return fail(row.error());
        reportRow(*row);
        rows.push_back(std::move(*row));
    }

    for (const Device& d : devices) {
        std::cout << d.label << ": " << d.name;
        if (d.bandwidthGBs)
            std::cout << ", copy bandwidth " << format("%.1f", *d.bandwidthGBs) << " GB/s";
        std::cout << "\n";
    }
    for (const BenchMesh& m : meshes)
        std::cout << m.name << ": " << m.mesh.triangleCount()
                  << " triangles, V = " << format("%.6g", m.exact.volume) << "\n";
    std::cout << frames << " frames per row after " << kWarmupFrames << " warm-up; errors: "
              << "largest over " << meshes.front().sweep.size() << " poses (3 orientations x "
              << kSweepLevels << " water levels)\n\n";
    printTable(rows);

    if (!createOutputFolder(o.out)) return kExitFailure;
    const fs::path csv = fs::path(o.out) / "bench.csv";
    const fs::path svg = fs::path(o.out) / "bench.svg";
    if (Status s = writeFileAtomically(csv, [&](std::ostream& out) { return writeCsv(rows, out); });
        !s.ok())
        return fail(s.error());
    const LogLogPlot plot = makePlot(rows);
    if (Status s = writeFileAtomically(svg, [&](std::ostream& out) { return writeSvg(plot, out); });
        !s.ok())
        return fail(s.error());
    std::cout << "\nwritten: " << csv.string() << ", " << svg.string() << "\n";
    return kExitOk;
}

}  // namespace plimsoll::cli
