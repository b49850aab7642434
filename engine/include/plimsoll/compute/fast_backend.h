// The fast CPU backend: the tiled evaluation of the shared evaluation core (plimsoll_eval/
// fast.hpp, single precision per entry, closed forms per tile) for every body, on the
// caller's task system or a thread pool of its own. The runtime library compiles the same
// core, so a bundle floats there as it does here.
#pragma once

#include "plimsoll/compute/compute.h"
#include "plimsoll/physics/buoyancy.h"

#include "plimsoll_eval/fast.hpp"
#include "plimsoll_eval/tasks.hpp"

#include <memory>

namespace plimsoll {

struct SurfaceTextures;

struct FastBackendOptions {
    int threads = 0;                  ///< of the default pool; 0: one per hardware thread
    plimsoll_eval::TaskSystem tasks;  ///< the caller's task system (else the pool)
    plimsoll_eval::FastOptions evaluation;
};

std::unique_ptr<BuoyancyBackend> createFastBackend(const FastBackendOptions& options = {});

/// A body's entries (relative to `centerOfMass`, object space) in the fast path's tiles.
plimsoll_eval::FastBody makeFastBody(const SurfaceTextures& textures,
                                     const Eigen::Vector3d& centerOfMass,
                                     const plimsoll_eval::FastOptions& options = {});

/// The water model as the fast path queries it (`water` must outlive the result).
plimsoll_eval::WaterSurface fastWaterSurface(const WaterModel& water);

/// One body through the fast path (what the backend does per request).
BuoyancyResult evaluateBuoyancyFast(const plimsoll_eval::FastBody& body, const BodyFrame& frame,
                                    const WaterModel& water, const FluidSettings& fluid,
                                    plimsoll_eval::FastScratch& scratch,
                                    plimsoll_eval::FastStats* stats = nullptr);

}  // namespace plimsoll
