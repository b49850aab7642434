// A body's level ladder (level_ladder.h).
#include "plimsoll/scene/level_ladder.h"

#include "plimsoll/compute/fast_backend.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/physics/pose.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace plimsoll {

std::vector<LevelPose> levelErrorPoses(const TriangleMesh& mesh,
                                       const Eigen::Vector3d& centerOfMass) {
    constexpr int kLevels = 9;
    const Eigen::Vector3d orientations[] = {{0, 0, 0}, {30, 0, 0}, {20, 40, 60}};
    std::vector<LevelPose> poses;
    for (const Eigen::Vector3d& degrees : orientations) {
        const Eigen::Matrix3d rotation =
            Pose::fromEulerDegrees(Eigen::Vector3d::Zero(), degrees).rotation;
        double low = 1e300, high = -1e300;
        for (const Eigen::Vector3d& p : mesh.positions) {
            const double y = (rotation * (p - centerOfMass)).y();
            low = std::min(low, y);
            high = std::max(high, y);
        }
        for (int i = 0; i < kLevels; ++i)
            poses.push_back({rotation, low + (high - low) * i / (kLevels - 1)});
    }
    return poses;
}

namespace {

BodyFrame frameAt(const LevelPose& p, const Eigen::Vector3d& centerOfMass) {
    BodyFrame frame;
    frame.pose.rotation = p.rotation;
    frame.pose.translation = -(p.rotation * centerOfMass);  // the centre of mass at the origin
    frame.centerOfMass = centerOfMass;
    return frame;
}

/// Microseconds per fast-path evaluation, one thread, half submerged on a Gerstner wave: the
/// best of three runs of at least 2 ms each.
double evaluationCost(const SurfaceTextures& textures, const Eigen::Vector3d& centerOfMass) {
    using Clock = std::chrono::steady_clock;
    const plimsoll_eval::FastBody body = makeFastBody(textures, centerOfMass);
    WaterModel water = WaterModel::flat(0.0);
    water.kind = WaterModel::Kind::Gerstner;
    water.waves.push_back(GerstnerWave{});
    BodyFrame frame;
    frame.pose.translation = Eigen::Vector3d(0.3, 0.0, 0.2);
    frame.centerOfMass = centerOfMass;
    frame.motion.linear = Eigen::Vector3d(0.1, 0.05, 0.0);
    plimsoll_eval::FastScratch scratch;
    double best = 1e300;
    for (int run = 0; run < 3; ++run) {
        int count = 0;
        const Clock::time_point start = Clock::now();
        double elapsed = 0;
        while (elapsed < 2e-3) {
            frame.time = 1e-3 * count;
            const BuoyancyResult r =
                evaluateBuoyancyFast(body, frame, water, FluidSettings{}, scratch);
            if (!std::isfinite(r.submergedVolume)) break;
            ++count;
            elapsed = std::chrono::duration<double>(Clock::now() - start).count();
        }
        best = std::min(best, 1e6 * elapsed / std::max(count, 1));
    }
    return best;
}

}  // namespace

Result<std::vector<int>> ladderSizes(std::vector<int> levels, int textureSize) {
    for (int size : levels) {
        if (size < kMinTextureSize || size > textureSize) {
            return makeError(ErrorKind::invalidArgument,
                             "lod level " + std::to_string(size) + " is outside " +
                                 std::to_string(kMinTextureSize) + ".." +
                                 std::to_string(textureSize) + " (the body's texture_size)");
        }
    }
    levels.push_back(textureSize);
    std::sort(levels.begin(), levels.end());
    levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
    return levels;
}

Result<std::vector<BuoyancyLevel>> bakeLevelLadder(const TriangleMesh& mesh,
                                                   const std::vector<int>& sizes, int finestSize,
                                                   std::shared_ptr<const SurfaceTextures> finest,
                                                   const BakeSettings& settings,
                                                   const Eigen::Vector3d& centerOfMass) {
    const std::vector<LevelPose> poses = levelErrorPoses(mesh, centerOfMass);
    const FluidSettings fluid;
    const WaterModel flatWater = WaterModel::flat(0.0);
    // The exact clip once per pose; the volume is the fully submerged pose's.
    std::vector<BuoyancyResult> exact;
    double volume = 0, radius = 0;
    for (const LevelPose& p : poses) {
        exact.push_back(evaluateBuoyancyExact(mesh, frameAt(p, centerOfMass), p.waterLevel, fluid));
        volume = std::max(volume, exact.back().submergedVolume);
    }
    for (const Eigen::Vector3d& v : mesh.positions)
        radius = std::max(radius, (v - centerOfMass).norm());
    const double forceScale = fluid.density * fluid.gravity * volume;
    const double torqueScale = forceScale * radius;
    std::vector<BuoyancyLevel> ladder;
    for (int size : sizes) {
        BuoyancyLevel level;
        level.size = size;
        if (size == finestSize && finest) {
            level.textures = finest;
        } else {
            BakeSettings s = settings;
            s.size = size;
            s.progress = {};
            Result<SurfaceTextures> baked = bakeSurfaceTextures(mesh, s);
            if (!baked)
                return withContext("lod level " + std::to_string(size) + ": ", baked.error());
            level.textures = std::make_shared<const SurfaceTextures>(std::move(*baked));
        }
        for (std::size_t i = 0; i < poses.size(); ++i) {
            WaterModel water = flatWater;
            water.level = poses[i].waterLevel;
            const BuoyancyResult r = evaluateBuoyancyReference(
                *level.textures, frameAt(poses[i], centerOfMass), water, fluid);
            const BuoyancyResult& x = exact[i];
            if (forceScale > 0) {
                level.forceError =
                    std::max({level.forceError, (r.force - x.force).norm() / forceScale,
                              (r.pressureForce - x.pressureForce).norm() / forceScale});
            }
            if (torqueScale > 0) {
                level.torqueError =
                    std::max({level.torqueError, (r.torque - x.torque).norm() / torqueScale,
                              (r.pressureTorque - x.pressureTorque).norm() / torqueScale});
            }
        }
        level.evaluationUs = evaluationCost(*level.textures, centerOfMass);
        ladder.push_back(std::move(level));
    }
    return ladder;
}

int coarsenessAt(double distance, double nearDistance, double margin, int current, int coarsest) {
    // Coarseness k covers (near 2^(k-1), near 2^k]; 0 covers [0, near].
    const auto bare = [&](double d) {
        if (!(d > nearDistance)) return 0;
        if (!std::isfinite(d)) return coarsest;
        return std::min(coarsest, static_cast<int>(std::ceil(std::log2(d / nearDistance))));
    };
    if (!(nearDistance > 0)) return coarsest;
    current = std::clamp(current, 0, coarsest);
    const int coarser = bare(distance / (1.0 + margin));  // beyond a boundary by the margin
    if (coarser > current) return coarser;
    const int finer = bare(distance * (1.0 + margin));  // within a boundary by the margin
    if (finer < current) return finer;
    return current;
}

}  // namespace plimsoll
