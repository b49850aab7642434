// The motion step with a radiation memory the caller chooses: the 1.x C calls step a body
// without radiation (plimsoll_body_step) or with a memory they were given
// (plimsoll_body_step_radiating), where stepBody uses the Body's own.
#pragma once

#include "plimsoll_runtime/runtime.hpp"

namespace plimsoll_runtime {

/// stepBody with `memory`'s radiation, or none when it is null.
void stepBodyWith(Body& body, BodyState& state, RadiationMemory* memory, const Water& water,
                  const Fluid& fluid, double time, double dt);

}  // namespace plimsoll_runtime
