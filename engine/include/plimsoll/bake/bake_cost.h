// What a bake will cost, said before it starts (a bake at kMaxTextureSize takes tens of
// seconds and gigabytes): estimated from the mesh's UV area, which the bake covers.
#pragma once

#include "plimsoll/core/limits.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/geometry/uv_layout.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace plimsoll {

struct BakeCost {
    double entries = 0;  ///< texel entries, about the covered texels
    double bytes = 0;    ///< peak memory of the bake and of writing its images
    double seconds = 0;  ///< on one core of the 2-core machine CI runs on (more cores: less)
};

/// Measured with `plimsoll bake assets/box.obj --size N` (N = 2048, 4096, 8192: 194 MB,
/// 575 MB and the figure docs/security.md gives): peak memory per entry (the entries' 68 bytes
/// and the bands' copies while they are joined) and a fixed part (the bands' accumulators, the
/// image rows being written); time per entry and per texel (the dense EXR rows are compressed
/// whether covered or not), on one core of a loaded 2-core machine.
inline constexpr double kBakeBytesPerEntry = 110.0;
inline constexpr double kBakeFixedBytes = 70.0 * (1 << 20);
inline constexpr double kBakeSecondsPerEntry = 1.0e-6;
inline constexpr double kBakeSecondsPerTexel = 2.5e-7;

/// The cost of baking `mesh` (its UVs as the bake places them) at size^2.
inline BakeCost estimateBakeCost(const TriangleMesh& mesh, int size) {
    BakeCost cost;
    if (!mesh.hasUvs()) return cost;
    const UvPlacement placement = fitUvsIntoUnitSquare(mesh);
    double uvArea = 0;
    for (const Triangle& t : mesh.triangles) {
        const Eigen::Vector2d a = mesh.uvs[t[0]], b = mesh.uvs[t[1]], c = mesh.uvs[t[2]];
        const Eigen::Vector2d u = b - a, v = c - a;
        uvArea += 0.5 * std::abs(u.x() * v.y() - u.y() * v.x());
    }
    const double texels = double(size) * double(size);
    cost.entries = std::min(1.0, uvArea * placement.scale * placement.scale) * texels;
    cost.bytes = kBakeFixedBytes + kBakeBytesPerEntry * cost.entries;
    cost.seconds = kBakeSecondsPerEntry * cost.entries + kBakeSecondsPerTexel * texels;
    return cost;
}

/// "a 8192^2 bake of about 19.2M texel entries needs about 2.0 GB of memory and 37 s": said
/// for bakes that need more than `threshold` bytes; empty below it.
inline std::string describeBakeCost(const TriangleMesh& mesh, int size,
                                    double threshold = 512.0 * (1 << 20)) {
    const BakeCost cost = estimateBakeCost(mesh, size);
    if (cost.bytes <= threshold) return {};
    std::ostringstream line;
    line.precision(3);
    line << "a " << size << "^2 bake of about " << cost.entries / 1e6
         << "M texel entries needs about " << formatBytes(cost.bytes) << " of memory and "
         << std::ceil(cost.seconds)
         << " s on one core (measured on the box asset; more cores bake faster)";
    return line.str();
}

}  // namespace plimsoll
