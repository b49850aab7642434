// Hydrostatics of a scene body (physics/hydrostatics.h) as the simulation starts it: its
// material's mass with the water graph's water, in the scene's medium. The CLI's
// `plimsoll hydrostatics` and the editor's panel both measure a body through here.
#pragma once

#include "plimsoll/core/result.h"
#include "plimsoll/physics/hydrostatics.h"
#include "plimsoll/scene/scene.h"

namespace plimsoll {

/// What floats: the body's mass properties plus, for a body with a water graph, the graph's
/// water (at its nodes, or with the graph's free-surface model at their low sides), upright,
/// the free surfaces of its partly filled nodes, and its openings: the graph's permeable
/// texel entries (painted permeable, an open hull's caps among them; those feeding a sealed
/// node left out), as the simulation lets water in. A body without a graph is sealed.
struct FloatingBody {
    HydrostaticBody body;
    double graphWater = 0;  ///< m^3 in the water graph
};
Result<FloatingBody> floatingBodyOf(const SceneBody& body, const MediumDesc& medium);

/// The settings for a scene's (or project's) medium and gravity vector: the medium's density
/// and the gravity's magnitude. Refuses zero gravity (nothing floats).
Result<HydrostaticsSettings> hydrostaticsSettingsOf(const MediumDesc& medium,
                                                    const Eigen::Vector3d& gravity);

}  // namespace plimsoll
