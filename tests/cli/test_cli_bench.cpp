// plimsoll bench end to end: a --quick run writes a table, a CSV with one row per measurement
// and an SVG plot; the errors it reports are finite and shrink as the textures grow. No timing
// assertions: speed is what the benchmark prints, not what a test can hold a machine to.
#include "plimsoll/compute/compute.h"

#include "cli_runner.h"
#include "test_support.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <unistd.h>

namespace plimsoll {
namespace test_cli_bench {
namespace {

namespace fs = std::filesystem;

using test::CommandOutput;
using test::runPlimsoll;

/// One CSV line split into fields ("..." quoting with doubled quotes, as device names need).
std::vector<std::string> splitCsvLine(const std::string& line) {
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
            fields.back() += '"';
            ++i;
        } else if (c == '"') {
            quoted = !quoted;
        } else if (c == ',' && !quoted) {
            fields.emplace_back();
        } else {
            fields.back() += c;
        }
    }
    return fields;
}

using CsvRow = std::map<std::string, std::string>;

std::vector<CsvRow> parseCsv(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> header = splitCsvLine(line);
    std::vector<CsvRow> rows;
    while (std::getline(in, line)) {
        const std::vector<std::string> fields = splitCsvLine(line);
        EXPECT_EQ(fields.size(), header.size()) << line;
        CsvRow row;
        for (std::size_t i = 0; i < std::min(fields.size(), header.size()); ++i)
            row[header[i]] = fields[i];
        rows.push_back(std::move(row));
    }
    return rows;
}

const char* const kErrorColumns[] = {"volume_error", "cob_error", "torque_error"};

TEST(CliBench, QuickRunWritesTableCsvAndSvg) {
    const fs::path out =
        fs::temp_directory_path() / ("plimsoll_bench_" + std::to_string(::getpid()));
    fs::remove_all(out);
    const std::optional<fs::path> spot = test::sharedMesh("spot.obj");
    const CommandOutput r = runPlimsoll("bench --quick --out '" + out.string() + "' --mesh '" +
                                        PLIMSOLL_SHARED_DIR "/meshes/spot.obj'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("vol err"), std::string::npos) << r.out;

    const std::string csv = test::readFile(out / "bench.csv");
    ASSERT_EQ(csv.rfind("kind,mesh,device,", 0), 0u) << csv.substr(0, 200);
    const std::vector<CsvRow> rows = parseCsv(csv);

    // One texture row per mesh, device and size (the reference included: --quick stays within
    // its 512 limit), one exact row per mesh, one batch row per OpenCL device.
    const std::size_t openClDevices = listComputeDevices().size();
    const std::size_t meshes = spot ? 2 : 1;
    const std::size_t quickSizes = 4;
    std::map<std::string, std::size_t> kinds;
    for (const CsvRow& row : rows) ++kinds[row.at("kind")];
    EXPECT_EQ(kinds["texture"], meshes * (openClDevices + 1) * quickSizes);
    EXPECT_EQ(kinds["exact"], meshes);
    EXPECT_EQ(kinds["batch"], openClDevices);
    EXPECT_EQ(rows.size(), kinds["texture"] + kinds["exact"] + kinds["batch"]);

    // errors[device][size] of the sphere, to check that they shrink with the texture size.
    std::map<std::string, std::map<int, CsvRow>> sphere;
    for (const CsvRow& row : rows) {
        if (row.at("kind") != "texture") continue;
        for (const char* column : kErrorColumns) {
            const double error = std::stod(row.at(column));
            EXPECT_TRUE(std::isfinite(error) && error >= 0)
                << column << " " << row.at("mesh") << " " << row.at("device") << " "
                << row.at("size");
        }
        if (row.at("mesh") == "sphere") sphere[row.at("device")][std::stoi(row.at("size"))] = row;
    }
    EXPECT_EQ(sphere.size(), openClDevices + 1);
    for (auto& [device, bySize] : sphere) {
        ASSERT_TRUE(bySize.count(64) && bySize.count(256)) << device;
        for (const char* column : kErrorColumns) {
            EXPECT_LT(std::stod(bySize[256].at(column)), std::stod(bySize[64].at(column)))
                << device << " " << column;
        }
    }

    const std::string svg = test::readFile(out / "bench.svg");
    EXPECT_EQ(svg.rfind("<svg", 0), 0u) << svg.substr(0, 200);
    fs::remove_all(out);
}

/// bench --realtime narrowed to the fast path on waves: the default grid of water samples and
/// the knob's other settings each get a row, and a coarser grid interpolates the waves less
/// well (errors against the reference at 128^2, measured 4.2e-4, 1.8e-4 and 7.5e-5 for 5, 7
/// and 9 samples a side at 64^2).
TEST(CliBench, RealtimeWavesRowsShowTheWaveGridTrade) {
    const fs::path out =
        fs::temp_directory_path() / ("plimsoll_bench_rt_" + std::to_string(::getpid()));
    fs::remove_all(out);
    const CommandOutput r = runPlimsoll(
        "bench --realtime --quick --frames 3 --scenario waves --method 'fast CPU' "
        "--bench-mesh sphere --sizes 64 --bodies 1 --out '" +
        out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::map<std::string, double> errorOf;
    for (const CsvRow& row : parseCsv(test::readFile(out / "realtime.csv"))) {
        EXPECT_EQ(row.at("scenario"), "moving, waves");
        EXPECT_EQ(row.at("size"), "64");
        EXPECT_GT(std::stod(row.at("us_per_body")), 0.0) << row.at("method");
        errorOf[row.at("method")] = std::stod(row.at("error"));
    }
    ASSERT_EQ(errorOf.size(), 6u);  // the default, three wave grids, two tile sizes
    const double e5 = errorOf.at("fast CPU (wave grid 5)"),
                 e7 = errorOf.at("fast CPU (wave grid 7)"), e9 = errorOf.at("fast CPU"),
                 e13 = errorOf.at("fast CPU (wave grid 13)");
    for (double e : {e5, e7, e9, e13}) EXPECT_TRUE(std::isfinite(e) && e > 0 && e < 1e-3) << e;
    // On waves a tile at the waterline takes one quadratic over all its entries: smaller
    // tiles sample the water more finely (16, 32, 64 entries: 8.9e-5, 1.3e-4, 2.1e-4 when
    // this was written).
    const double e16 = errorOf.at("fast CPU (tiles 16)"), e64 = errorOf.at("fast CPU (tiles 64)");
    EXPECT_LT(e16, e9);
    EXPECT_LT(e9, e64);
    EXPECT_GT(e5, e7);
    EXPECT_GT(e7, e9);
    EXPECT_NE(r.out.find("moving, waves, sphere: within"), std::string::npos) << r.out;
    fs::remove_all(out);
}

/// bench --integrators: one row per integrator and time step; the symplectic and fourth-order
/// integrators keep the energy finite, and explicit Euler (the paper's) gains energy at the
/// coarse step where semi-implicit Euler does not.
TEST(CliBench, RadiationQuickRunWritesCostWithAndWithout) {
    const fs::path out =
        fs::temp_directory_path() / ("plimsoll_bench_rad_" + std::to_string(::getpid()));
    fs::remove_all(out);
    const CommandOutput r = runPlimsoll("bench --radiation --quick --out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("panels"), std::string::npos) << r.out;
    const std::vector<CsvRow> rows = parseCsv(test::readFile(out / "bench_radiation.csv"));
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].at("run"), "without");
    EXPECT_EQ(rows[1].at("run"), "with");
    for (const CsvRow& row : rows)
        EXPECT_GT(std::stod(row.at("seconds_per_step")), 0.0) << row.at("run");
}

/// bench --fleet: a fleet of one bundle holds a tenth or less of what one load per boat holds,
/// and both rows step the same number of boats (the times are the bench's to report).
TEST(CliBench, FleetQuickRunComparesOneBundleWithOneLoadPerBoat) {
    const fs::path out =
        fs::temp_directory_path() / ("plimsoll_bench_fleet_" + std::to_string(::getpid()));
    fs::remove_all(out);
    const std::string project =
        std::string(PLIMSOLL_SOURCE_DIR) + "/projects/damaged_boat.plim.json";
    const CommandOutput r = runPlimsoll("bench --fleet --quick --frames 3 --fleet-project '" +
                                        project + "' --out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("flooding / dry"), std::string::npos) << r.out;
    std::map<std::string, CsvRow> rows;
    for (const CsvRow& row : parseCsv(test::readFile(out / "bench_fleet.csv")))
        rows[row.at("case") + "/" + row.at("threads")] = row;
    const CsvRow& shared = rows.at("flooding boats, one bundle (2.0)/1");
    const CsvRow& separate = rows.at("flooding boats, one load each (1.x)/1");
    EXPECT_EQ(shared.at("bodies"), separate.at("bodies"));
    EXPECT_EQ(shared.at("bundles"), "1");
    EXPECT_EQ(separate.at("bundles"), separate.at("bodies"));
    EXPECT_LE(10 * std::stod(shared.at("memory_bytes")), std::stod(separate.at("memory_bytes")));
    for (const auto& [name, row] : rows) EXPECT_GT(std::stod(row.at("frame_ms")), 0.0) << name;
    // The one-body rows run on the calling thread, so they carry its CPU time, and the flooding
    // ones their ratio to the dry row on the same water.
    for (const char* water : {"", ", flat water"}) {
        const std::string dry = std::string("one body, water load only (dry)") + water + "/1";
        const std::string flooding =
            std::string("one body, flooding (graph step + load)") + water + "/1";
        EXPECT_GT(std::stod(rows.at(dry).at("cpu_us_per_body")), 0.0) << dry;
        EXPECT_GT(std::stod(rows.at(flooding).at("cpu_us_per_body")), 0.0) << flooding;
        EXPECT_GT(std::stod(rows.at(flooding).at("flooding_over_dry_cpu")), 0.0) << flooding;
        EXPECT_GT(std::stod(rows.at(flooding).at("flooding_over_dry_wall")), 0.0) << flooding;
    }
    EXPECT_EQ(shared.at("cpu_us_per_body"), "");
    fs::remove_all(out);
}

/// bench --scene: the resting bodies all fall asleep and then cost no evaluation, where the
/// same scene without sleeping evaluates every body every sub-step.
TEST(CliBench, SceneQuickRunSleepsEveryRestingBody) {
    const fs::path out =
        fs::temp_directory_path() / ("plimsoll_bench_scene_" + std::to_string(::getpid()));
    fs::remove_all(out);
    const CommandOutput r =
        runPlimsoll("bench --scene --quick --frames 2 --out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::vector<CsvRow> rows = parseCsv(test::readFile(out / "bench_scene.csv"));
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].at("asleep"), "0");
    EXPECT_EQ(std::stod(rows[0].at("evaluations_per_frame")),
              4.0 * std::stod(rows[0].at("bodies")));
    EXPECT_EQ(rows[1].at("asleep"), rows[1].at("bodies"));
    EXPECT_EQ(std::stod(rows[1].at("evaluations_per_frame")), 0.0);
    EXPECT_GT(std::stoi(rows[1].at("frames_to_sleep")), 0);
    // Level of detail: the same bodies on waves all at 64^2, then by distance with every
    // sub-step and with fewer steps at coarser levels; those within 50 m at 64^2 exactly, the
    // rest coarser, fewer entries evaluated, and with fewer steps fewer evaluations.
    const std::vector<CsvRow> lod = parseCsv(test::readFile(out / "bench_scene_lod.csv"));
    ASSERT_EQ(lod.size(), 3u);
    EXPECT_EQ(lod[0].at("at_64"), lod[0].at("bodies"));
    EXPECT_EQ(std::stod(lod[0].at("error_beyond")), 0.0);
    const double bodies = std::stod(lod[0].at("bodies"));
    EXPECT_EQ(std::stod(lod[0].at("evaluations_per_frame")), 4.0 * bodies);
    // (a late switch evaluates both levels once more)
    EXPECT_GE(std::stod(lod[1].at("evaluations_per_frame")), 4.0 * bodies);
    EXPECT_LT(std::stod(lod[1].at("evaluations_per_frame")), 4.1 * bodies);
    for (std::size_t k : {1u, 2u}) {
        SCOPED_TRACE(k);
        EXPECT_GT(std::stoi(lod[k].at("bodies_50m")), 0);
        EXPECT_EQ(std::stod(lod[k].at("error_50m")), 0.0);
        EXPECT_GT(std::stoi(lod[k].at("at_16")), std::stoi(lod[k].at("at_64")));
        EXPECT_GT(std::stod(lod[k].at("error_beyond")), 0.0);
    }
    EXPECT_LT(std::stod(lod[2].at("evaluations_per_frame")), 2.0 * bodies);
    EXPECT_GE(std::stod(lod[2].at("evaluations_per_frame")), bodies);
    fs::remove_all(out);
}

TEST(CliBench, IntegratorsQuickRunWritesDriftCsv) {
    const fs::path out =
        fs::temp_directory_path() / ("plimsoll_bench_int_" + std::to_string(::getpid()));
    fs::remove_all(out);
    const CommandOutput r = runPlimsoll("bench --integrators --quick --out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("final drift"), std::string::npos) << r.out;

    const std::string csv = test::readFile(out / "bench_integrators.csv");
    ASSERT_EQ(csv.rfind("integrator,dt_s,", 0), 0u) << csv.substr(0, 200);
    const std::vector<CsvRow> rows = parseCsv(csv);
    ASSERT_EQ(rows.size(), 9u) << csv;

    // Rows by integrator and steps per second (1 / dt).
    std::map<std::string, std::map<int, CsvRow>> byIntegrator;
    for (const CsvRow& row : rows) {
        const int rate = static_cast<int>(std::lround(1.0 / std::stod(row.at("dt_s"))));
        byIntegrator[row.at("integrator")][rate] = row;
    }
    ASSERT_EQ(byIntegrator.size(), 3u) << csv;
    for (const auto& [integrator, byRate] : byIntegrator) {
        EXPECT_EQ(byRate.size(), 3u) << integrator;
        for (int rate : {240, 60, 15}) EXPECT_TRUE(byRate.count(rate)) << integrator << " " << rate;
    }
    for (const char* integrator : {"semi-implicit-euler", "rk4"}) {
        for (const auto& [rate, row] : byIntegrator[integrator]) {
            EXPECT_EQ(row.at("diverged"), "0") << integrator << " 1/" << rate;
            for (const char* column : {"final_drift", "max_drift"}) {
                ASSERT_FALSE(row.at(column).empty())
                    << integrator << " 1/" << rate << " " << column;
                EXPECT_TRUE(std::isfinite(std::stod(row.at(column))))
                    << integrator << " 1/" << rate << " " << column;
            }
        }
    }

    // At dt = 1/15 s explicit Euler gains energy: more than semi-implicit Euler drifts either
    // way (or it diverged outright).
    const CsvRow& explicitCoarse = byIntegrator["explicit-euler"][15];
    const double semiDrift = std::stod(byIntegrator["semi-implicit-euler"][15].at("final_drift"));
    if (explicitCoarse.at("diverged") != "1") {
        EXPECT_GT(std::stod(explicitCoarse.at("final_drift")), std::abs(semiDrift)) << csv;
    }
    fs::remove_all(out);
}

}  // namespace
}  // namespace test_cli_bench
}  // namespace plimsoll
