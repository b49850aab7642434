// plimsoll bench --scene: what a scene of many bodies costs the World a frame, on the fast CPU
// path (the editor's and simulate's default). N flat boxes of half the water's density rest on
// flat water, 3 m apart: first with sleeping off (every body evaluated and integrated every
// frame), then with the default sleeping, after the bodies fell asleep (docs/design.md,
// "Sleeping bodies"). Written to DIR/bench_scene.csv.
// Then level of detail (docs/design.md, "Level of detail"): N boxes with the level ladder 16,
// 32, 64 on two Gerstner waves, spread evenly over 1 km x 1 km around a point of interest at
// the centre, all at 64^2 (today's fixed size) against the distance policy (64^2 within 50 m,
// one level coarser each doubling), with every sub-step and with fewer steps at coarser levels
// (the default), with the force error of each distance band against the 64^2 result at the
// same state. Written to DIR/bench_scene_lod.csv.
#include "cli/bench.h"
#include "cli/commands.h"

#include "plimsoll/compute/fast_backend.h"
#include "plimsoll/io/file_util.h"
#include "plimsoll/samples/primitives.h"
#include "plimsoll/scene/scene.h"
#include "plimsoll/scene/world.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
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

/// N flat boxes of half the water's density (`desc` gives the rest) baked once and shared, on a
/// square grid `spacing` apart from (origin, y, origin), in fresh water.
Result<Scene> boxGrid(BodyDesc desc, int count, double spacing, double origin, double y) {
    desc.name = "box";
    desc.mesh = "generated";
    desc.textureSize = 64;
    desc.material.density = 500.0;
    BodyParts parts;
    parts.mesh = std::make_shared<const TriangleMesh>(makeBox(Eigen::Vector3d(1.0, 0.25, 0.8)));
    Result<SceneBody> baked = bakeSceneBody(desc, std::move(parts));
    if (!baked) return baked.error();
    Scene scene;
    scene.medium.density = 1000.0;
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
    for (int i = 0; i < count; ++i) {
        SceneBody body = *baked;
        body.desc.name = "box" + std::to_string(i);
        body.label = "body '" + body.desc.name + "'";
        body.desc.position =
            Eigen::Vector3d(origin + spacing * (i % side), y, origin + spacing * (i / side));
        scene.bodies.push_back(std::move(body));
    }
    return scene;
}

/// N damped boxes 3 m apart let go 1 mm above their draft on flat water: they settle within a
/// second or two.
Result<Scene> restingBoxes(int count, bool sleep) {
    BodyDesc desc;
    desc.linearDamping = 4.0;
    desc.angularDamping = 4.0;
    Result<Scene> scene = boxGrid(desc, count, 3.0, 0.0, 0.001);
    if (!scene) return scene;
    scene->water = WaterModel::flat(0.0);
    scene->simulation.sleep.enabled = sleep;
    return scene;
}

/// Mean time and buoyancy evaluations a frame over `frames` frames of `world`.
Status timeFrames(World& world, int frames, double& frameMs, double& evaluationsPerFrame) {
    const std::size_t evaluations = world.statistics().buoyancyEvaluations;
    const Clock::time_point start = Clock::now();
    for (int f = 0; f < frames; ++f) {
        if (Status s = world.advanceFrame(); !s.ok()) return s;
    }
    frameMs = 1e3 * std::chrono::duration<double>(Clock::now() - start).count() / frames;
    evaluationsPerFrame =
        static_cast<double>(world.statistics().buoyancyEvaluations - evaluations) / frames;
    return Ok{};
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
    if (Status s = timeFrames(world, frames, row.frameMs, row.evaluationsPerFrame); !s.ok())
        return s.error();
    row.asleep = static_cast<int>(std::count_if(world.bodies().begin(), world.bodies().end(),
                                                [](const SimulatedBody& b) { return b.asleep; }));
    return row;
}

/// Two Gerstner waves: a 40 m swell and a 15 m sea.
WaterModel benchWaves() {
    WaterModel water;
    water.kind = WaterModel::Kind::Gerstner;
    GerstnerWave swell;
    swell.amplitude = 0.4;
    swell.wavelength = 40.0;
    swell.steepness = 0.4;
    GerstnerWave sea;
    sea.amplitude = 0.15;
    sea.wavelength = 15.0;
    sea.direction = Eigen::Vector2d(0.6, 0.8);
    sea.steepness = 0.4;
    water.waves = {swell, sea};
    return water;
}

constexpr double kLodSpread = 1000.0;  ///< m, the side of the square the bodies cover
constexpr double kLodNear = 50.0;      ///< m, the distance policy's nearDistance

struct LodRow {
    std::string name;
    int bodies = 0;
    double frameMs = 0, evaluationsPerFrame = 0;
    int subSteps = 0;
    std::map<int, int> atLevel;  ///< texels per side -> bodies
    /// Largest |F - F_64| / (rho g V) per band of distance (m: up to 50, 100, 200, beyond).
    std::array<double, 4> bandError{};
    std::array<int, 4> bandBodies{};
};

/// N laddered boxes (16, 32, 64) baked once and shared, spread evenly over the square (one at
/// the point of interest, the centre), on waves.
Result<Scene> spreadBoxes(int count) {
    BodyDesc desc;
    desc.lod = LodDesc{{16, 32}};
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
    Result<Scene> scene = boxGrid(desc, count, kLodSpread / side, -0.5 * kLodSpread, 0.0);
    if (!scene) return scene;
    scene->water = benchWaves();
    scene->simulation.sleep.enabled = false;
    return scene;
}

int bandOf(double distance) {
    return distance <= kLodNear       ? 0
           : distance <= 2 * kLodNear ? 1
           : distance <= 4 * kLodNear ? 2
                                      : 3;
}

/// The policies measured: every body at 64^2; by distance with every sub-step; by distance
/// with fewer steps at coarser levels (the default).
enum class LodCase { finest, distanceEveryStep, distance };

Result<LodRow> measureLod(const Scene& scene, LodCase which, int frames) {
    Result<std::unique_ptr<World>> made = World::create(scene, createFastBackend());
    if (!made) return made.error();
    World& world = **made;
    LodRow row;
    row.name = which == LodCase::finest ? "waves, all at 64^2"
               : which == LodCase::distanceEveryStep
                   ? "waves, distance policy (64^2 within 50 m), every sub-step"
                   : "waves, distance policy (64^2 within 50 m)";
    row.bodies = static_cast<int>(world.bodies().size());
    row.subSteps = world.scene().simulation.subSteps;
    if (which != LodCase::finest) {
        LevelPolicy policy;
        policy.kind = LevelPolicy::Kind::distance;
        policy.nearDistance = kLodNear;
        policy.fewerStepsWhenCoarser = which == LodCase::distance;
        if (Status s = world.setLevelPolicy(policy); !s.ok()) return s.error();
    }
    // 1 s: the bodies take to the waves, and every switch's blend is over.
    for (int f = 0; f < 60; ++f) {
        if (Status s = world.advanceFrame(); !s.ok()) return s.error();
    }
    if (Status s = timeFrames(world, frames, row.frameMs, row.evaluationsPerFrame); !s.ok())
        return s.error();
    // Each body's force now against its 64^2 level's at the same state (the fast path, as the
    // World evaluates): the pressure integral the World applies on waves.
    const std::vector<SceneBody>& bodies = world.scene().bodies;
    const plimsoll_eval::FastBody finest =
        makeFastBody(*bodies[0].textures, bodies[0].mass->centerOfMass);
    plimsoll_eval::FastScratch scratch;
    for (std::size_t i = 0; i < world.bodies().size(); ++i) {
        const SimulatedBody& body = world.bodies()[i];
        ++row.atLevel[body.levelSize];
        BodyFrame frame;
        frame.pose = body.pose();
        frame.motion.linear = linearVelocity(body.state, body.mass);
        frame.motion.angular = angularVelocity(body.state, body.mass);
        frame.centerOfMass = body.mass.centerOfMass;
        frame.time = world.time();
        const BuoyancyResult at64 =
            evaluateBuoyancyFast(finest, frame, world.scene().water, body.fluid, scratch);
        const double scale = body.fluid.density * body.fluid.gravity * body.volume;
        // body.buoyancy is from the last step's start: evaluate the level in use now instead.
        const std::vector<BuoyancyLevel>* levels = world.levels(i);
        BuoyancyResult now = at64;
        if (levels && body.levelSize != 64) {
            for (const BuoyancyLevel& level : *levels) {
                if (level.size != body.levelSize) continue;
                now = evaluateBuoyancyFast(makeFastBody(*level.textures, body.mass.centerOfMass),
                                           frame, world.scene().water, body.fluid, scratch);
            }
        }
        const int band = bandOf((body.state.position - Eigen::Vector3d::Zero()).norm());
        ++row.bandBodies[band];
        row.bandError[band] =
            std::max(row.bandError[band], (now.pressureForce - at64.pressureForce).norm() / scale);
    }
    return row;
}

int runLodBench(const BenchOptions& o, int count, int frames) {
    std::printf("  %d boxes on waves over 1 km x 1 km, all at 64^2 and by distance...\n", count);
    std::fflush(stdout);
    Result<Scene> scene = spreadBoxes(count);
    if (!scene) {
        std::fprintf(stderr, "error: bench --scene: %s\n", scene.error().message.c_str());
        return 1;
    }
    const std::vector<BuoyancyLevel>& ladder = *scene->bodies[0].levels;
    std::vector<std::vector<std::string>> levelLines{
        {"level", "entries", "force error (of rho g V)", "torque error", "us/evaluation"}};
    for (const BuoyancyLevel& level : ladder) {
        levelLines.push_back({std::to_string(level.size) + "^2",
                              std::to_string(level.textures->coveredCount()),
                              format("%.2e", level.forceError), format("%.2e", level.torqueError),
                              format("%.2f", level.evaluationUs)});
    }
    printAligned(levelLines, 1);
    std::vector<LodRow> rows;
    for (LodCase which : {LodCase::finest, LodCase::distanceEveryStep, LodCase::distance}) {
        Result<LodRow> row = measureLod(*scene, which, frames);
        if (!row) {
            std::fprintf(stderr, "error: bench --scene: %s\n", row.error().message.c_str());
            return 1;
        }
        rows.push_back(*row);
    }
    std::vector<std::vector<std::string>> lines{{"scene", "bodies", "ms/frame", "ms/sub-step",
                                                 "evaluations/frame", "at 64/32/16", "error <=50 m",
                                                 "<=100 m", "<=200 m", "beyond"}};
    std::ostringstream csv;
    csv << "scene,bodies,frame_ms,substep_ms,evaluations_per_frame,at_64,at_32,at_16,"
           "error_50m,error_100m,error_200m,error_beyond,bodies_50m\n";
    for (const LodRow& r : rows) {
        const auto at = [&](int size) {
            const auto it = r.atLevel.find(size);
            return it == r.atLevel.end() ? 0 : it->second;
        };
        std::vector<std::string> line{
            r.name,
            std::to_string(r.bodies),
            format("%.3f", r.frameMs),
            format("%.3f", r.frameMs / r.subSteps),
            format("%.1f", r.evaluationsPerFrame),
            std::to_string(at(64)) + "/" + std::to_string(at(32)) + "/" + std::to_string(at(16))};
        for (int b = 0; b < 4; ++b) line.push_back(format("%.2e", r.bandError[b]));
        lines.push_back(line);
        csv << '"' << r.name << "\"," << r.bodies << ',' << r.frameMs << ','
            << r.frameMs / r.subSteps << ',' << r.evaluationsPerFrame << ',' << at(64) << ','
            << at(32) << ',' << at(16);
        for (int b = 0; b < 4; ++b) csv << ',' << r.bandError[b];
        csv << ',' << r.bandBodies[0] << '\n';
    }
    printAligned(lines, 1);
    if (rows[0].frameMs > 0) {
        std::printf(
            "by distance, a frame costs %.1f%% of the fixed 64^2 frame (%.1f%% with every "
            "sub-step); %d bodies within 50 m, their force %.2e of rho g V from their 64^2 "
            "result\n",
            100.0 * rows[2].frameMs / rows[0].frameMs, 100.0 * rows[1].frameMs / rows[0].frameMs,
            rows[2].bandBodies[0], rows[2].bandError[0]);
    }
    const fs::path file = fs::path(o.out) / "bench_scene_lod.csv";
    if (Status s = writeFileAtomically(
            file, [&](std::ostream& out) { return static_cast<bool>(out << csv.str()); });
        !s.ok()) {
        std::fprintf(stderr, "error: %s\n", s.error().message.c_str());
        return 1;
    }
    std::printf("wrote %s\n", file.string().c_str());
    return 0;
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
    return runLodBench(o, count, frames);
}

}  // namespace plimsoll::cli
