// A body's level ladder (docs/design.md, "Level of detail"): its mesh baked at a short ladder
// of texture sizes, each a true bake, each with its force and torque error against the exact
// clip measured once when the ladder is made ("its stated error") and its cost per evaluation
// on the fast CPU path. And the rule by which the World picks a level from a distance (or an
// importance) with hysteresis: within LevelPolicy::nearDistance the finest level, one level
// coarser each time the distance doubles.
#pragma once

#include "plimsoll/bake/bake.h"
#include "plimsoll/core/result.h"
#include "plimsoll/geometry/mesh.h"

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace plimsoll {

/// One level of a body's ladder.
struct BuoyancyLevel {
    int size = 0;  ///< texels per side
    std::shared_ptr<const SurfaceTextures> textures;
    /// Its stated force error: the largest |F - F_exact| / (rho g V) over the ladder's poses
    /// (levelErrorPoses), F both Archimedes' force and the pressure integral, F_exact the exact
    /// clip of the mesh (evaluateBuoyancyExact), V the mesh's volume. The C++ reference
    /// evaluates the texture (the bake's error; the fast path adds at most its float rounding).
    double forceError = 0;
    /// The largest |T - T_exact| / (rho g V R) over the same poses, about the centre of mass,
    /// R the mesh's farthest vertex from it.
    double torqueError = 0;
    /// Microseconds per evaluation on the fast CPU path, one thread, half submerged on waves
    /// (measured when the ladder is made; what the budget policy adds up).
    double evaluationUs = 0;
};

/// The poses a level's error is measured over: three orientations (upright, 30 degrees of
/// heel, (20, 40, 60) degrees) about the centre of mass, each at 9 water levels from the
/// lowest to the highest vertex (dry to fully submerged), as plimsoll bench does.
struct LevelPose {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    double waterLevel = 0;  ///< m, with the centre of mass at the origin
};
std::vector<LevelPose> levelErrorPoses(const TriangleMesh& mesh,
                                       const Eigen::Vector3d& centerOfMass);

/// Bakes `mesh` at each of `sizes` (ascending, unique) except `finestSize`, whose bake
/// `finest` is taken as it is, and measures each level's error about `centerOfMass` (object
/// space, the body's own mass properties') and its cost. Coarsest first, finest last.
Result<std::vector<BuoyancyLevel>> bakeLevelLadder(const TriangleMesh& mesh,
                                                   const std::vector<int>& sizes, int finestSize,
                                                   std::shared_ptr<const SurfaceTextures> finest,
                                                   const BakeSettings& settings,
                                                   const Eigen::Vector3d& centerOfMass);

/// The ladder's sizes for a body: `levels` sorted, made unique, `textureSize` added; refuses a
/// size outside kMinTextureSize..textureSize, naming it.
Result<std::vector<int>> ladderSizes(std::vector<int> levels, int textureSize);

/// How coarse a body should be at `distance` (m) from the point of interest: 0 (the finest)
/// within `nearDistance`, k + 1 within nearDistance 2^(k+1). `current` is the coarseness in
/// use: it changes only when the distance is beyond the boundary by more than `margin` (a
/// fraction of it), so a body moved back and forth across a boundary by less does not flip.
/// The result is at most `coarsest`.
int coarsenessAt(double distance, double nearDistance, double margin, int current, int coarsest);

}  // namespace plimsoll
