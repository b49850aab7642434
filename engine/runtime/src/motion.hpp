// The motion step with a radiation memory the caller chooses: the 1.x C calls step a body
// without radiation (plimsoll_body_step) or with a memory they were given
// (plimsoll_body_step_radiating), where stepBody uses the Body's own.
#pragma once

#include "plimsoll_runtime/runtime.hpp"

#include "plimsoll_eval/sleep.hpp"

namespace plimsoll_runtime {

/// stepBody with `memory`'s radiation, or none when it is null, and without sleeping; true when
/// the body's water graph moved water.
bool stepBodyWith(Body& body, BodyState& state, RadiationMemory* memory, const Water& water,
                  const Fluid& fluid, double time, double dt);

/// The bundle's sleep settings as the evaluation core's rule takes them.
plimsoll_eval::SleepSettings sleepSettingsOf(const BundleWorld::Sleep& sleep);

/// The water's height above `point` and the water's speed there: what decides whether the
/// water is calm where a body floats (the World's surfaceAbove).
void surfaceAbove(const Water& water, const Vec3& point, double time, double& height,
                  double& speed);

}  // namespace plimsoll_runtime
