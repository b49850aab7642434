// The water graph's models as a project's "water_graph" and a bundle manifest's write them:
// one writer, so the two files cannot drift apart (their readers check them differently: the
// project's names every problem for the editor, the runtime's its manifest's own rules).
#pragma once

#include "plimsoll/graph/graph.h"

namespace plimsoll {

/// Sets the models' members of `out` (a JSON object, ordered or not), in the order files show.
template <class JsonObject>
void writeGraphModels(const GraphSettings& settings, JsonObject& out) {
    out["inflow"] = inflowModelName(settings.inflow);
    out["inflow_rate"] = settings.inflowRate;
    out["discharge_coefficient"] = settings.dischargeCoefficient;
    out["flow"] = flowModelName(settings.flow);
    out["diffusion_pressure"] = settings.diffusionPressure;
    out["free_surface"] = settings.freeSurface;
    out["seed"] = settings.seed;
}

}  // namespace plimsoll
