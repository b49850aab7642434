// A body's level ladder (level_ladder.h).
#include "plimsoll/scene/level_ladder.h"

#include "plimsoll/compute/fast_backend.h"
#include "plimsoll/core/limits.h"
#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/physics/massprops.h"
#include "plimsoll/physics/pose.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

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

LevelErrorMeter::LevelErrorMeter(const TriangleMesh& mesh, const Eigen::Vector3d& centerOfMass)
    : centerOfMass_(centerOfMass), poses_(levelErrorPoses(mesh, centerOfMass)) {
    const FluidSettings fluid;
    // The exact clip once per pose; the volume is the fully submerged pose's.
    double volume = 0, radius = 0;
    for (const LevelPose& p : poses_) {
        exact_.push_back(
            evaluateBuoyancyExact(mesh, frameAt(p, centerOfMass), p.waterLevel, fluid));
        volume = std::max(volume, exact_.back().submergedVolume);
    }
    for (const Eigen::Vector3d& v : mesh.positions)
        radius = std::max(radius, (v - centerOfMass).norm());
    forceScale_ = fluid.density * fluid.gravity * volume;
    torqueScale_ = forceScale_ * radius;
}

LevelErrorMeter::Errors LevelErrorMeter::measure(const SurfaceTextures& textures) const {
    const FluidSettings fluid;
    Errors errors;
    for (std::size_t i = 0; i < poses_.size(); ++i) {
        WaterModel water = WaterModel::flat(poses_[i].waterLevel);
        const BuoyancyResult r =
            evaluateBuoyancyReference(textures, frameAt(poses_[i], centerOfMass_), water, fluid);
        const BuoyancyResult& x = exact_[i];
        if (forceScale_ > 0) {
            errors.force = std::max({errors.force, (r.force - x.force).norm() / forceScale_,
                                     (r.pressureForce - x.pressureForce).norm() / forceScale_});
        }
        if (torqueScale_ > 0) {
            errors.torque = std::max({errors.torque, (r.torque - x.torque).norm() / torqueScale_,
                                      (r.pressureTorque - x.pressureTorque).norm() / torqueScale_});
        }
    }
    return errors;
}

namespace {

Result<std::shared_ptr<const SurfaceTextures>> bakeAt(const TriangleMesh& mesh, int size,
                                                      const BakeSettings& settings) {
    BakeSettings s = settings;
    s.size = size;
    s.progress = {};
    Result<SurfaceTextures> baked = bakeSurfaceTextures(mesh, s);
    if (!baked) return baked.error();
    return std::make_shared<const SurfaceTextures>(std::move(*baked));
}

std::string shortNumber(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1e", value);
    return text;
}

}  // namespace

Result<std::vector<BuoyancyLevel>> bakeLevelLadder(const TriangleMesh& mesh,
                                                   const std::vector<int>& sizes, int finestSize,
                                                   std::shared_ptr<const SurfaceTextures> finest,
                                                   const BakeSettings& settings,
                                                   const Eigen::Vector3d& centerOfMass) {
    const LevelErrorMeter meter(mesh, centerOfMass);
    std::vector<BuoyancyLevel> ladder;
    for (int size : sizes) {
        BuoyancyLevel level;
        level.size = size;
        if (size == finestSize && finest) {
            level.textures = finest;
        } else {
            Result<std::shared_ptr<const SurfaceTextures>> baked = bakeAt(mesh, size, settings);
            if (!baked)
                return withContext("lod level " + std::to_string(size) + ": ", baked.error());
            level.textures = std::move(*baked);
        }
        const LevelErrorMeter::Errors errors = meter.measure(*level.textures);
        level.forceError = errors.force;
        level.torqueError = errors.torque;
        level.evaluationUs = evaluationCost(*level.textures, centerOfMass);
        ladder.push_back(std::move(level));
    }
    return ladder;
}

Result<LevelChoice> chooseLevelForTolerance(const TriangleMesh& mesh, double tolerance,
                                            const BakeSettings& settings, int maxSize) {
    if (!(tolerance > 0) || !std::isfinite(tolerance)) {
        return makeError(ErrorKind::invalidArgument,
                         "tolerance " + shortNumber(tolerance) + " is not a positive number");
    }
    const LevelErrorMeter meter(mesh, exactSolidMassProperties(mesh, 1.0).centerOfMass);
    LevelChoice choice;
    choice.tolerance = tolerance;
    for (int size = kMinTextureSize; size <= maxSize; size *= 2) {
        Result<std::shared_ptr<const SurfaceTextures>> baked = bakeAt(mesh, size, settings);
        if (!baked)
            return withContext("texture size " + std::to_string(size) + ": ", baked.error());
        const LevelErrorMeter::Errors errors = meter.measure(**baked);
        if (errors.force <= tolerance) {
            choice.size = size;
            choice.forceError = errors.force;
            choice.torqueError = errors.torque;
            choice.textures = std::move(*baked);
            return choice;
        }
        choice.coarser.emplace_back(size, errors.force);
    }
    const std::string finest = choice.coarser.empty()
                                   ? std::string("no size was tried")
                                   : "the finest, " + std::to_string(choice.coarser.back().first) +
                                         ", has a force error of " +
                                         shortNumber(choice.coarser.back().second);
    return makeError(ErrorKind::invalidArgument,
                     "no texture size up to " + std::to_string(maxSize) + " meets the tolerance " +
                         shortNumber(tolerance) + " (" + finest +
                         "): give a larger tolerance, or a texture_size by name");
}

std::string describeLevelChoice(const LevelChoice& choice) {
    std::string text = std::to_string(choice.size) + " texels (force error " +
                       shortNumber(choice.forceError) + " within " + shortNumber(choice.tolerance);
    if (!choice.coarser.empty()) {
        text += "; " + std::to_string(choice.coarser.back().first) + ": " +
                shortNumber(choice.coarser.back().second);
    }
    return text + ")";
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
