// Painted maps (permeability, surface density, thickness): greyscale images over the mesh's own
// UV layout, at their own resolution (independent of the physics texture size); io/
// painted_map_io.h reads and writes them as 8- or 16-bit PNG. Values are normalised to 0..1;
// what 1 means (kg/m^2, m, ...) is the caller's scale.
#pragma once

#include <vector>

namespace plimsoll {

struct SurfaceTextures;

struct PaintedMap {
    int width = 0;
    int height = 0;
    /// Row-major, row 0 at the top of the image (v = 1), values 0..1.
    std::vector<float> values;

    /// Bilinear sample at mesh uv (u right, v up), clamped at the edges.
    double sample(double u, double v) const;
};

/// The map's value times `scale` at every entry of the textures (its texel centre, taken back
/// to mesh uv through the bake's placement): e.g. surface density per entry for
/// textureShellMassProperties.
std::vector<double> sampleAtTexels(const PaintedMap& map, const SurfaceTextures& textures,
                                   double scale);

}  // namespace plimsoll
