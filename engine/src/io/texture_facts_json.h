// What every manifest that describes baked textures says about them (the bake's manifest.json
// and the runtime bundle's): one place, so the two cannot drift apart.
#pragma once

#include "plimsoll/bake/bake.h"

#include <nlohmann/json.hpp>

namespace plimsoll {

inline nlohmann::json textureFactsJson(const SurfaceTextures& t) {
    return {{"texture_size", t.size},
            {"covered_texels", t.distinctTexelCount()},
            {"texel_samples", t.coveredCount()},
            {"uv_coverage", t.uvCoverage()},
            {"surface_area", t.surfaceArea()},
            {"closure_error", t.closureError()},
            {"uv_placement",
             {{"scale", t.placement.scale},
              {"offset", {t.placement.offset.x(), t.placement.offset.y()}}}}};
}

}  // namespace plimsoll
