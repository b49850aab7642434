// What the viewport paints over a mesh: a painted map, or one of the physics textures (coverage,
// PT, AVT), as an RGBA8 image over the mesh's UVs. GL-free: the renderer uploads the image.
#pragma once

#include "document/document.h"

#include "plimsoll/geometry/uv_layout.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace plimsoll::editor {

enum class Overlay { None, Permeability, Density, Thickness, Coverage, Position, AreaVector };
inline constexpr Overlay kOverlays[] = {
    Overlay::None,     Overlay::Permeability, Overlay::Density,   Overlay::Thickness,
    Overlay::Coverage, Overlay::Position,     Overlay::AreaVector};

/// "none", "permeability", "density", "thickness", "coverage", "position", "area".
const char* overlayName(Overlay overlay);
std::optional<Overlay> parseOverlay(const std::string& name);
std::optional<MapChannel> overlayChannel(Overlay overlay);

/// The colour ramp of scalar maps: 0 is blue (0.10, 0.25, 0.90), 1 is orange (0.95, 0.45, 0.05),
/// linear between (red above blue exactly when the value is above 0.5).
Eigen::Vector3f rampColour(double value);

struct OverlayImage {
    int width = 0;
    int height = 0;
    /// RGBA8, row 0 at v = 0 (OpenGL's order).
    std::vector<std::uint8_t> rgba;
    /// Image uv = scale * mesh uv + offset (identity for painted maps; the bake's placement
    /// for physics textures).
    UvPlacement placement;
};

/// What an overlay's colours mean, for the view's legend.
struct OverlayLegend {
    bool ramp = false;      ///< the colours are rampColour from `low` (0) to `high` (1)
    std::string low, high;  ///< the ends' values, with units
    std::string meaning;    ///< one line: the quantity and its unit
};
/// The legend of `overlay` on `body` (its shell gives the density map's scale; null: none).
OverlayLegend overlayLegend(Overlay overlay, const BodyDesc* body);

/// A corner of the view for a label drawn over it.
enum class ViewCorner { LowerLeft, LowerRight };
/// Where a label of `size` drawn over `view` goes (its top-left corner, window pixels, y down):
/// in `corner`, unless one of the `avoid` rectangles (floating windows, other labels) covers
/// it; then just above one of them, or beside it (away from the corner's side) where there is
/// no room above (the view's first `topMargin` pixels keep the view's title line); the first
/// such place clear of them all, in the order given, and the corner itself where none is.
/// The view's legend keeps clear of the Live preview window this way, which opens in the
/// lower-left corner, and the preview's performance readout of both.
Eigen::Vector2f overlayPlace(const Eigen::AlignedBox2f& view, const Eigen::Vector2f& size,
                             std::span<const Eigen::AlignedBox2f> avoid, ViewCorner corner,
                             float topMargin = 24);

/// The hover readout's physics at a surface point of `body` (object space), at the body's pose
/// in the project: how deep under the surface it lies (the project's water at `time`) and the
/// medium's hydrostatic pressure there (rho |g| depth), or how far above it; and, when the body
/// has a water graph, the node its texel feeds (the engine's rule, nearestNode). One line each.
std::string surfacePointPhysics(const Document& document, std::size_t body,
                                const Eigen::Vector3d& object, double time);

/// A painted map's overlay image (the ramp, rows flipped to OpenGL's order).
OverlayImage overlayOfMap(const PaintedMap& map);

/// The overlay image of a body (a body without a map of that channel shows its uniform value:
/// 0 for permeability, 1 for density and thickness).
Result<OverlayImage> buildOverlay(Document& document, std::size_t body, Overlay overlay);
/// The overlay of a painted channel (empty for the physics overlays and None).
OverlayImage buildMapOverlay(const Document& document, std::size_t body, Overlay overlay);
/// A physics overlay (coverage, position, area vector) of baked textures (empty otherwise).
OverlayImage overlayOfTextures(const SurfaceTextures& textures, Overlay overlay);

}  // namespace plimsoll::editor
