// plimsoll_web_bench BUNDLE_FOLDER [STEPS]: the native side of web/README.md's figures, the same
// work web/package/bench/bench.mjs times in WebAssembly: loading the bundle from memory (files
// read first), one evaluation on the bundle's own water, one body step (stepBody, the bundle's
// water, 1/240 s) and one frame of the bundle's own world (Simulation). Medians of 5 rounds;
// prints one line of JSON. Wall-clock times: figures for a README, not for tests.
#include "plimsoll_runtime/runtime.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace rt = plimsoll_runtime;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

static double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: plimsoll_web_bench BUNDLE_FOLDER [STEPS]\n");
        return 2;
    }
    const int steps = argc > 2 ? std::atoi(argv[2]) : 2000;
    std::vector<std::pair<std::string, std::string>> contents;
    for (const auto& e : fs::recursive_directory_iterator(argv[1])) {
        if (!e.is_regular_file()) continue;
        std::ifstream in(e.path(), std::ios::binary);
        contents.emplace_back(fs::relative(e.path(), argv[1]).generic_string(),
                              std::string(std::istreambuf_iterator<char>(in), {}));
    }
    std::vector<rt::MemoryFile> files;
    for (const auto& [path, bytes] : contents) files.push_back({path, bytes.data(), bytes.size()});
    std::vector<double> load, evaluate, step, frame;
    std::string error;
    std::unique_ptr<rt::Bundle> bundle;
    for (int round = 0; round < 5; ++round) {
        const auto t0 = Clock::now();
        bundle = rt::loadBundleFromMemory(files, "bench", error);
        // The first evaluation builds the tiles: part of what a load costs before the first frame.
        if (bundle) bundle->evaluate({}, {}, bundle->world().water.water(), bundle->fluid(), 0.0);
        load.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        if (!bundle) {
            std::fprintf(stderr, "plimsoll_web_bench: %s\n", error.c_str());
            return 1;
        }
    }
    const rt::Water water = bundle->world().water.water();
    // The bundle's fluid already carries its world's density and gravity (as index.js reads it).
    const rt::Fluid fluid = bundle->fluid();
    const double dt = 1.0 / 240.0;
    double sink = 0;
    for (int round = 0; round < 5; ++round) {
        rt::Pose pose = bundle->world().startPose;
        auto t0 = Clock::now();
        for (int i = 0; i < steps; ++i) {
            pose.position.y = bundle->world().startPose.position.y + 0.001 * (i % 50);
            sink += bundle->evaluate(pose, {}, water, fluid, i * dt).submergedVolume;
        }
        evaluate.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() /
                           steps);
        rt::Body body(*bundle);
        rt::BodyState state;
        state.pose = bundle->world().startPose;
        t0 = Clock::now();
        for (int i = 0; i < steps; ++i) rt::stepBody(body, state, water, fluid, i * dt, dt);
        step.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() /
                       steps);
        sink += state.pose.position.y;
        auto simulation = rt::Simulation::create(*bundle, error);
        const int frames = std::max(1, steps / 4);
        t0 = Clock::now();
        for (int i = 0; i < frames; ++i) simulation->advanceFrame(water, error);
        frame.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() /
                        frames);
        sink += simulation->centerOfMass().y;
    }
    std::printf(
        "{\"body\": \"%s\", \"load_ms\": %.2f, \"evaluate_us\": %.1f, \"step_us\": %.1f, "
        "\"frame_us\": %.1f, "
        "\"check\": %.3g}\n",
        bundle->body().c_str(), median(load), median(evaluate), median(step), median(frame), sink);
    return 0;
}
