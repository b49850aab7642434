// Level of detail (docs/design.md, "Level of detail"): how a body with a level ladder picks its
// level each frame, and how a switch is blended so that it never kicks. The editor's World and
// the runtime's Simulation both follow these rules, so that one policy gives one level in both.
// Levels are indexed coarsest first: 0 the coarsest, `finest` the body's own texture size.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <limits>
#include <utility>
#include <vector>

namespace plimsoll_eval {

/// How coarse a body should be at `distance` (m) from the point of interest: 0 (the finest)
/// within `nearDistance`, k + 1 within nearDistance 2^(k+1). `current` is the coarseness in
/// use: it changes only when the distance is beyond the boundary by more than `margin` (a
/// fraction of it), so a body moved back and forth across a boundary by less does not flip.
/// The result is at most `coarsest`.
inline int coarsenessAt(double distance, double nearDistance, double margin, int current,
                        int coarsest) {
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

/// The policies: every body at its finest level; by distance from a point of interest; by an
/// importance in 0..1 (1 the finest, each halving one level coarser); within a budget of
/// microseconds a frame for all bodies (the nearest first).
enum class LevelPolicyKind { finest, distance, importance, budget };

/// The level index (0 the coarsest, `finest` the finest) the distance rule picks for a body at
/// `distance` now at level `current`.
inline int levelAtDistance(double distance, double nearDistance, double margin, int current,
                           int finest) {
    return finest - coarsenessAt(distance, nearDistance, margin, finest - current, finest);
}

/// The level an importance picks: importance 1 acts as the distance nearDistance / sqrt 2,
/// 1/2 as nearDistance sqrt 2, ... (the middle of each band, in doublings), so the margin never
/// holds a body off its level; 0 the coarsest.
inline int levelOfImportance(double importance, double nearDistance, double margin, int current,
                             int finest) {
    constexpr double kSqrt2 = 1.41421356237309504880;
    const double distance = importance > 0 ? nearDistance / (importance * kSqrt2)
                                           : std::numeric_limits<double>::infinity();
    return levelAtDistance(distance, nearDistance, margin, current, finest);
}

/// Temporal level of detail: the integration steps a frame a body takes at `level`. At its
/// finest level the project's `subSteps`; each coarser level half as many, since a body far
/// enough away to be evaluated coarsely gains nothing from a finer step than its forces, but
/// never fewer than `stableSteps` (what its hydrostatic stiffness and spin need for a stable
/// step, World::subStepsFor) nor fewer than one.
inline int stepsAtLevel(int subSteps, int stableSteps, int level, int finest) {
    const int coarseness = std::clamp(finest - level, 0, 30);
    return std::max({1, stableSteps, subSteps >> coarseness});
}

/// On a frame of `frameSteps` sub-steps, how many sub-steps each of a body's steps spans when
/// it needs at least `steps` a frame: the longest stride that divides the frame evenly and
/// still gives that many, so that its steps fall on the frame's sub-steps 0, stride, 2 stride...
inline int strideFor(int frameSteps, int steps) {
    for (int stride = frameSteps / std::max(1, steps); stride > 1; --stride) {
        if (frameSteps % stride == 0) return stride;
    }
    return 1;
}

/// The stride of a body's steps on a frame of `frameSteps` sub-steps when it is at `level`:
/// 1 at its finest level or with temporal level of detail off (`fewer`), so that it takes every
/// sub-step of the frame as a body without a ladder does; otherwise
/// strideFor(frameSteps, stepsAtLevel(subSteps, stableSteps, level, finest)).
inline int stepStride(bool fewer, int frameSteps, int subSteps, int stableSteps, int level,
                      int finest) {
    if (!fewer || level >= finest) return 1;
    return strideFor(frameSteps, stepsAtLevel(subSteps, stableSteps, level, finest));
}

/// One body's part in the budget's greedy pass: its distance to the point of interest and each
/// level's cost per evaluation (us, coarsest first).
struct BudgetEntry {
    double distance = 0;
    const double* costs = nullptr;
    std::size_t levels = 0;
};

/// The budget's levels: every body starts at its coarsest level (always paid), then the bodies
/// nearest the point of interest, one after the other, take the finest level the rest of
/// `budgetUs` pays for; a body's level cost is `evaluations` times its cost per evaluation.
/// Fills `levels` (one per entry).
inline void budgetLevels(const std::vector<BudgetEntry>& bodies, double evaluations,
                         double budgetUs, std::vector<int>& levels) {
    levels.assign(bodies.size(), 0);
    double spent = 0;
    std::vector<std::pair<double, std::size_t>> order;
    order.reserve(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        if (bodies[i].levels == 0) continue;
        spent += bodies[i].costs[0] * evaluations;
        order.emplace_back(bodies[i].distance, i);
    }
    std::sort(order.begin(), order.end());
    for (const auto& [distance, i] : order) {
        const BudgetEntry& b = bodies[i];
        for (int k = static_cast<int>(b.levels) - 1; k > 0; --k) {
            const double extra = (b.costs[k] - b.costs[0]) * evaluations;
            if (spent + extra <= budgetUs) {
                spent += extra;
                levels[i] = k;
                break;
            }
        }
    }
}

/// A body's level in use and the state of its switching. A body switches at most once every
/// holdFrames frames (and not while asleep); at a switch both levels are evaluated at the same
/// state and their difference (plus what was left of a blend still running) is added to the new
/// level's results with a weight that falls linearly from 1 to 0 over blendFrames x sub-steps
/// sub-steps: the force moves from the old level's to the new one's without a jump beyond the
/// two levels' difference over the blend's sub-steps.
struct LevelSwitch {
    int level = 0;       ///< index in use
    int framesHeld = 0;  ///< frames since the last switch
    int blendSteps = 0;  ///< sub-steps the blend lasts
    int blendLeft = 0;   ///< sub-steps it has left

    /// Counts a frame; true when the body may switch now (held for holdFrames frames).
    bool countFrame(int holdFrames) {
        if (framesHeld < std::numeric_limits<int>::max() / 2) ++framesHeld;
        return framesHeld >= holdFrames;
    }
    /// The weight of the running blend's difference now (0: none).
    double weight() const {
        return blendLeft > 0 ? static_cast<double>(blendLeft) / blendSteps : 0.0;
    }
    /// Switches to `target`; returns the weight of the blend that was still running (the share
    /// of its difference that the new blend carries on).
    double switchTo(int target) {
        const double carried = weight();
        level = target;
        framesHeld = 0;
        blendLeft = 0;
        return carried;
    }
    /// Starts the blend of a switch: blendFrames frames of `subSteps` sub-steps.
    void startBlend(int blendFrames, int subSteps) {
        blendSteps = blendLeft = std::max(1, blendFrames * subSteps);
    }
    /// One sub-step of the blend has passed.
    void advance() {
        if (blendLeft > 0) --blendLeft;
    }
};

}  // namespace plimsoll_eval
