// plimsoll bench --realtime: the issue of real time on a CPU in one table (bench_realtime.cpp).
#pragma once

#include <string>
#include <vector>

namespace plimsoll::cli {

struct RealtimeBenchOptions {
    std::string out = "bench_out";
    bool quick = false;
    int frames = 0;  ///< 0: the default (200, 30 with --quick)
    // Narrowing a run to one measurement (to profile it); empty: everything.
    std::vector<int> sizes;              ///< texture sizes (default 32 to 2048, 32 to 128 quick)
    std::vector<std::string> scenarios;  ///< "rest", "moving", "waves"
    std::vector<std::string> methods;    ///< methods whose label starts with one of these
    std::vector<std::string> meshes;     ///< "sphere", "buoy"
    std::vector<int> bodies;             ///< body counts: 1, 100, 1000
};

/// Runs the scenarios and writes OUT/realtime.csv and OUT/realtime.svg; returns the exit code.
int runRealtimeBench(const RealtimeBenchOptions& options);

}  // namespace plimsoll::cli
