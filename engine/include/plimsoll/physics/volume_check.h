// The texture method's submerged volume against the exact clip of the mesh, at one pose in flat
// water: the accuracy figure `plimsoll buoyancy --compare-exact` prints and the editor's live
// preview shows for the current pose (one function, so that the two can never disagree).
#pragma once

#include "plimsoll/physics/buoyancy.h"
#include "plimsoll/physics/buoyancy_backend.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/core/result.h"

#include <cstddef>

namespace plimsoll {

struct SubmergedVolumeCheck {
    double texture = 0;        ///< m^3, the backend's texel sum (paper eq. 10)
    double exact = 0;          ///< m^3, the mesh clipped against the plane
    double error = 0;          ///< texture - exact, m^3
    double relativeError = 0;  ///< error / exact; 0 when the exact volume is 0
};

/// Evaluates body `bodyId` of `backend` (registered with its textures) at `frame` in flat water
/// at `waterLevel` (m), and the exact submerged volume of `mesh` (closed, object space, the
/// mesh those textures were baked from) at the same pose. The exact reference exists only for
/// flat water: for waves, pass the mean level.
Result<SubmergedVolumeCheck> checkSubmergedVolume(BuoyancyBackend& backend, std::size_t bodyId,
                                                  const TriangleMesh& mesh, const BodyFrame& frame,
                                                  double waterLevel, const FluidSettings& fluid);

}  // namespace plimsoll
