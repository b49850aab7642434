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
#include "plimsoll/physics/buoyancy.h"

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <string>
#include <utility>
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

/// A texture's error against the exact clip of its mesh over levelErrorPoses, as a level
/// states it (BuoyancyLevel::forceError, torqueError) and as a tolerance is met. The exact
/// clip is computed once, when the meter is made; each measure evaluates the texture only.
class LevelErrorMeter {
public:
    LevelErrorMeter(const TriangleMesh& mesh, const Eigen::Vector3d& centerOfMass);
    struct Errors {
        double force = 0;   ///< BuoyancyLevel::forceError
        double torque = 0;  ///< BuoyancyLevel::torqueError
    };
    Errors measure(const SurfaceTextures& textures) const;

private:
    Eigen::Vector3d centerOfMass_;
    std::vector<LevelPose> poses_;
    std::vector<BuoyancyResult> exact_;
    double forceScale_ = 0, torqueScale_ = 0;
};

/// Bakes `mesh` at each of `sizes` (ascending, unique) except `finestSize`, whose bake
/// `finest` is taken as it is, and measures each level's error about `centerOfMass` (object
/// space, the body's own mass properties') and its cost. Coarsest first, finest last.
Result<std::vector<BuoyancyLevel>> bakeLevelLadder(const TriangleMesh& mesh,
                                                   const std::vector<int>& sizes, int finestSize,
                                                   std::shared_ptr<const SurfaceTextures> finest,
                                                   const BakeSettings& settings,
                                                   const Eigen::Vector3d& centerOfMass);

/// The texture size an accuracy budget picks (a body's "tolerance"): the smallest of 16, 32,
/// 64, ... that meets it, and the measured errors that show it does.
struct LevelChoice {
    double tolerance = 0;  ///< the largest force error allowed, a share of rho g V
    int size = 0;          ///< texels per side
    double forceError = 0, torqueError = 0;  ///< its measured errors (LevelErrorMeter)
    /// The coarser sizes tried first and their force errors, each above the tolerance.
    std::vector<std::pair<int, double>> coarser;
    std::shared_ptr<const SurfaceTextures> textures;  ///< its bake
};

/// The largest texture a tolerance may pick: a finer bake than this is a size the user asks
/// for by name, not one a search should spend memory on.
inline constexpr int kToleranceMaxTextureSize = 1024;

/// Bakes `mesh` at 16, 32, 64, ... up to `maxSize` and stops at the first size whose force
/// error (LevelErrorMeter) is at most `tolerance`. The meter's point is the solid's centroid:
/// the force error, which the tolerance bounds, does not depend on it, and the body's own
/// centre of mass is known only once a size is baked. Fails, naming the tolerance and the
/// finest size's error, when none up to maxSize meets it.
Result<LevelChoice> chooseLevelForTolerance(const TriangleMesh& mesh, double tolerance,
                                            const BakeSettings& settings,
                                            int maxSize = kToleranceMaxTextureSize);

/// "256 texels (force error 5.5e-04 within 1e-03; 128: 2.2e-03)": the choice in one line.
std::string describeLevelChoice(const LevelChoice& choice);

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
