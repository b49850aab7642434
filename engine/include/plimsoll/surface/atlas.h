// The physics atlas: which UV map a body is baked with. The texture method needs a bijective
// map from the surface into the unit square; game assets often lack one (no UVs, two mirrored
// halves sharing one half of the texture, overlapping or tiled charts). Then a physics-only
// atlas is generated: the surface is split into charts that project flat without folds, the
// charts are scaled alike (so a texel stands for about the same world area everywhere) and
// packed with gutters.
#pragma once

#include "plimsoll/bake/bake.h"
#include "plimsoll/geometry/mesh.h"
#include "plimsoll/core/result.h"
#include "plimsoll/geometry/validate.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plimsoll {

/// Per body, on the command line (--atlas) and in the project ("atlas").
enum class AtlasMode {
    Mesh,      ///< the mesh's own UVs; refused, with the reason, when they are not bijective
    Auto,      ///< the mesh's UVs when bijective, a generated atlas otherwise (and says so)
    Generate,  ///< always a generated atlas
};

const char* atlasModeName(AtlasMode mode);  ///< "mesh", "auto", "generate"
std::optional<AtlasMode> parseAtlasMode(std::string_view name);

/// Bumped whenever the generator's output changes, so that cached atlases are regenerated.
inline constexpr int kAtlasGeneratorVersion = 1;

struct AtlasSettings {
    /// Texels per side the packing is laid out for: gutters are whole texels at this size (a
    /// bake at another size still works; only the gutter width in its texels changes).
    int textureSize = 256;
    /// Empty texels between two charts (half of it between a chart and the texture's border).
    int gutterTexels = 2;
    /// Every triangle of a chart faces within this angle of the chart's projection axis, so a
    /// texel covers between 1 and 1/cos(angle) times the world area of the flattest texels.
    double maxChartAngleDegrees = 66.0;
    /// A chart reaches at most this times sqrt(surface area) from its seed (in its plane):
    /// compact charts pack densely, and rings (the top of a torus faces one way all round)
    /// cannot form. 0: no limit. With 66 degrees and 0.15 the shared meshes' atlases cover
    /// 59-65% of the texture at N = 256.
    double maxChartRadius = 0.15;
    ProgressCallback progress;  ///< fraction done, 0..1
};

struct PhysicsAtlas {
    /// The input's triangles in the same order and with the same corner order (so triangle ids
    /// of bakes and deformation frames still match), vertices split where charts meet, UVs
    /// inside the unit square.
    TriangleMesh mesh;
    std::vector<std::uint32_t> sourceVertex;     ///< per vertex: the input vertex it copies
    std::vector<std::uint32_t> chartOfTriangle;  ///< per triangle, 0..chartCount-1
    std::size_t chartCount = 0;
    double uvCoverage = 0;  ///< UV area of the charts over the unit square, 0..1
    double uvPerMetre = 0;  ///< scale of every chart: UV units per metre of projected surface
};

/// Generates the atlas. Deterministic: the same mesh and settings give the same UVs. Needs a
/// non-empty mesh with finite positions; the input's own UVs are ignored. Fails (naming the
/// mesh) when the charts cannot be packed at the texture size with at least one texel each.
Result<PhysicsAtlas> generatePhysicsAtlas(const TriangleMesh& mesh, const AtlasSettings& settings);

/// Why the mesh's own UVs cannot be baked ("" when they can): its UV errors, one line each,
/// with their codes and the share of the surface they affect.
std::string meshUvRefusal(const ValidationReport& report);

/// The UVs a body is baked with.
struct AtlasChoice {
    TriangleMesh mesh;  ///< the input, or the input with a generated atlas
    bool generated = false;
    std::size_t chartCount = 0;  ///< of a generated atlas
    /// What the user should know ("" when the mesh's own UVs are used as they are).
    std::string notice;
};

/// Where a generated atlas comes from: generatePhysicsAtlas, or a cache of it
/// (io/atlas_cache.h), so that painted maps stay attached to one atlas.
using AtlasSource = std::function<Result<PhysicsAtlas>(const TriangleMesh&, const AtlasSettings&)>;

/// Applies `mode` to a validated mesh. Only UV problems matter here; whether the mesh is a
/// closed solid is the caller's concern. A generated atlas comes from `source`
/// (generatePhysicsAtlas when empty).
Result<AtlasChoice> chooseAtlas(const TriangleMesh& mesh, const ValidationReport& report,
                                AtlasMode mode, const AtlasSettings& settings,
                                const AtlasSource& source = {});

}  // namespace plimsoll
