// plimsoll bench --scene: what a scene of many bodies costs the World a frame, on the fast CPU
// path (the editor's and simulate's default). N flat boxes of half the water's density rest on
// flat water, 3 m apart: first with sleeping off (every body evaluated and integrated every
// frame), then with the default sleeping, after the bodies fell asleep (docs/design.md,
// "Sleeping bodies"). Written to DIR/bench_scene.csv.
#include "cli/bench.h"
#include "cli/commands.h"

#include "plimsoll/compute/fast_backend.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/scene.h"
#include "plimsoll/scene/world.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

namespace plimsoll::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct SceneRow {
    std::string name;
    int bodies = 0, asleep = 0, framesToSleep = 0;
    double frameMs = 0, evaluationsPerFrame = 0;
};

/// N boxes baked once and shared, each let go at its draft on flat water.
Result<Scene> restingBoxes(int count, bool sleep) {
    BodyDesc desc;
    desc.name = "box";
    desc.mesh = "generated";
    desc.textureSize = 64;
    desc.material.density = 500.0;
    desc.linearDamping = 4.0;
    desc.angularDamping = 4.0;
    BodyParts parts;
    parts.mesh = std::make_shared<const TriangleMesh>(makeBox(Eigen::Vector3d(1.0, 0.25, 0.8)));
    Result<SceneBody> baked = bakeSceneBody(desc, std::move(parts));
    if (!baked) return baked.error();
    Scene scene;
    scene.medium.density = 1000.0;
    scene.water = WaterModel::flat(0.0);
    scene.simulation.sleep.enabled = sleep;
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
    for (int i = 0; i < count; ++i) {
        SceneBody body = *baked;
        body.desc.name = "box" + std::to_string(i);
        body.label = "body '" + body.desc.name + "'";
        // 1 mm above the draft: the boxes settle within a second or two.
        body.desc.position = Eigen::Vector3d(3.0 * (i % side), 0.001, 3.0 * (i / side));
        scene.bodies.push_back(std::move(body));
    }
    return scene;
}

Result<SceneRow> measure(int count, bool sleep, int frames) {
    Result<Scene> scene = restingBoxes(count, sleep);
    if (!scene) return scene.error();
    Result<std::unique_ptr<World>> made = World::create(std::move(*scene), createFastBackend());
    if (!made) return made.error();
    World& world = **made;
    SceneRow row;
    row.name = sleep ? "at rest, sleeping on (asleep)" : "at rest, sleeping off";
    row.bodies = count;
    // Settle (and, with sleeping, fall asleep): 10 s at most.
    const int settle = static_cast<int>(std::lround(10.0 / world.scene().simulation.timeStep));
    for (int f = 0; f < settle; ++f) {
        if (Status s = world.advanceFrame(); !s.ok()) return s.error();
        const bool all = std::all_of(world.bodies().begin(), world.bodies().end(),
                                     [](const SimulatedBody& b) { return b.asleep; });
        if (sleep && all) {
            row.framesToSleep = f + 1;
            break;
        }
    }
    const std::size_t evaluations = world.statistics().buoyancyEvaluations;
    const Clock::time_point start = Clock::now();
    for (int f = 0; f < frames; ++f) {
        if (Status s = world.advanceFrame(); !s.ok()) return s.error();
    }
    row.frameMs = 1e3 * std::chrono::duration<double>(Clock::now() - start).count() / frames;
    row.evaluationsPerFrame =
        static_cast<double>(world.statistics().buoyancyEvaluations - evaluations) / frames;
    row.asleep = static_cast<int>(std::count_if(world.bodies().begin(), world.bodies().end(),
                                                [](const SimulatedBody& b) { return b.asleep; }));
    return row;
}

}  // namespace

int runSceneBench(const BenchOptions& o) {
    if (!createOutputFolder(o.out)) return 1;
    const int count = o.quick ? 100 : 1000;
    const int frames = o.frames > 0 ? o.frames : (o.quick ? 10 : 60);
    std::vector<SceneRow> rows;
    for (bool sleep : {false, true}) {
        std::printf("  %d boxes at rest on flat water, sleeping %s...\n", count,
                    sleep ? "on" : "off");
        std::fflush(stdout);
        Result<SceneRow> row = measure(count, sleep, frames);
        if (!row) {
            std::fprintf(stderr, "error: bench --scene: %s\n", row.error().message.c_str());
            return 1;
        }
        rows.push_back(*row);
    }
    std::vector<std::vector<std::string>> lines{
        {"scene", "bodies", "asleep", "frames to sleep", "ms/frame", "evaluations/frame"}};
    std::ostringstream csv;
    csv << "scene,bodies,asleep,frames_to_sleep,frame_ms,evaluations_per_frame\n";
    for (const SceneRow& r : rows) {
        lines.push_back({r.name, std::to_string(r.bodies), std::to_string(r.asleep),
                         std::to_string(r.framesToSleep), format("%.3f", r.frameMs),
                         format("%.1f", r.evaluationsPerFrame)});
        csv << '"' << r.name << "\"," << r.bodies << ',' << r.asleep << ',' << r.framesToSleep
            << ',' << r.frameMs << ',' << r.evaluationsPerFrame << '\n';
    }
    printAligned(lines, 1);
    if (rows.size() == 2 && rows[0].frameMs > 0) {
        std::printf("asleep, a frame costs %.1f%% of the awake frame\n",
                    100.0 * rows[1].frameMs / rows[0].frameMs);
    }
    const fs::path file = fs::path(o.out) / "bench_scene.csv";
    if (Status s = writeFileAtomically(
            file, [&](std::ostream& out) { return static_cast<bool>(out << csv.str()); });
        !s.ok()) {
        std::fprintf(stderr, "error: %s\n", s.error().message.c_str());
        return 1;
    }
    std::printf("wrote %s\n", file.string().c_str());
    return 0;
}

}  // namespace plimsoll::cli
