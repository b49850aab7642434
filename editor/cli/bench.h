// plimsoll bench: its options, and what each measurement file runs. bench_command.cpp parses
// the command line; bench_accuracy.cpp measures the texture method's speed against accuracy,
// bench_integrators.cpp the integrators' energy drift against time step, bench_realtime.cpp the
// real-time table; bench_table.cpp prints their tables.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace plimsoll::cli {

/// Seconds of CPU the calling thread has run: on a shared machine the wall clock also counts
/// the time other processes held the core (bench_fleet.cpp).
double threadCpuSeconds();

/// The C++ reference visits every entry in double: beyond 512^2 it only shows it is slow.
inline constexpr int kReferenceMaxSize = 512;

struct BenchOptions {
    std::vector<int> sizes;
    int frames = 0;  ///< 0: the default for the mode
    std::string out = "bench_out";
    std::string mesh = "../shared/meshes/spot.obj";
    bool quick = false;
    bool sizesGiven = false;
    bool integrators = false;  ///< only the integrators' energy drift table
    bool realtime = false;     ///< only the real-time scenarios table (bench_realtime.cpp)
    // --realtime filters (RealtimeBenchOptions).
    std::vector<std::string> scenarios, methods, meshes;
    std::vector<int> bodies;
    bool radiation = false;             ///< only radiation's cost per step (bench_radiation.cpp)
    std::string projects = "projects";  ///< --radiation: the sample projects' folder
    bool fleet = false;                 ///< only the runtime's fleet table (bench_fleet.cpp)
    bool scene = false;                 ///< only the World's cost of many bodies (bench_scene.cpp)
    std::string fleetProject = "projects/damaged_boat.plim.json";
};

/// The speed against accuracy table: DIR/bench.csv and DIR/bench.svg; returns the exit code.
int runAccuracyBench(const BenchOptions& o);
/// The integrators' energy drift table: DIR/bench_integrators.csv; returns the exit code.
int runIntegratorBench(const BenchOptions& o);

/// Radiation's load time and cost per step, with and without: DIR/bench_radiation.csv.
int runRadiationBench(const BenchOptions& o);

/// The runtime's cost for one dry body, one flooding body and a fleet of flooding boats on one
/// bundle against one load each: DIR/bench_fleet.csv.
int runFleetBench(const BenchOptions& o);

/// The World's cost a frame for many bodies at rest, awake and asleep: DIR/bench_scene.csv.
int runSceneBench(const BenchOptions& o);

/// Creates the output folder `out` (and its parents); false with the message printed.
bool createOutputFolder(const std::string& out);

/// A table cell: `value` printed with the printf conversion `spec`.
std::string format(const char* spec, double value);
/// Columns padded to their widest cell: the first `names` columns left-aligned (names), the
/// others right-aligned so the digits of their numbers line up.
void printAligned(const std::vector<std::vector<std::string>>& lines, std::size_t names);

}  // namespace plimsoll::cli
