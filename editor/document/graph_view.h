// What the views show of a water graph, GL-free: a colour per node, the surface coloured by
// the node each texel feeds (texelNodeMap, paper 4.2) and by the segment of an automatic
// segmentation (its preview before "Apply"), as overlay images over the physics texture
// (overlay.h); and the 2D schematic of nodes and pipes beside the 3D view.
#pragma once

#include "document/overlay.h"

#include "plimsoll/bake/bake.h"
#include "plimsoll/graph_auto/graph_auto.h"
#include "plimsoll/graph/graph.h"

#include <Eigen/Core>

#include <functional>

namespace plimsoll::editor {

/// A distinct colour for node (or segment) i: hues around the wheel by the golden angle.
Eigen::Vector3f nodeColour(std::size_t i);

/// The physics texture with every covered texel in the colour of the node it feeds; texels of
/// no node (an empty graph) stay transparent.
OverlayImage feedOverlay(const WaterGraph& graph, const SurfaceTextures& textures);

/// Segment of each texel entry: the segment of the triangle whose centroid is nearest to the
/// texel's surface point (brute force over a coarse grid of triangle centroids). `progress`
/// gets 0..1.
std::vector<int> texelSegments(const TriangleMesh& mesh, const MeshSegmentation& segmentation,
                               const SurfaceTextures& textures,
                               const std::function<void(double)>& progress = {});

/// The physics texture coloured by segment (nodeColour of the segment index).
OverlayImage segmentOverlay(const std::vector<int>& texelSegment, const SurfaceTextures& textures);

/// A schematic of a graph in a width x height canvas (pixels, y down): every node a box at its
/// place in the body's profile (y up; across, object x or z, whichever the nodes spread over
/// more: the hull's length, as a side view draws its tanks), then pushed apart until no two
/// boxes overlap (nodes side by side across the profile get separate boxes, in index order);
/// pipes join the box centres.
struct SchematicLayout {
    std::vector<Eigen::Vector2f> centre;  ///< per node, canvas pixels
    Eigen::Vector2f box{0, 0};            ///< every box's width and height
    int along = 0;                        ///< the object axis across the canvas: 0 (x) or 2 (z)
    /// Metres of the profile per canvas pixel, across and up (one axis along which the nodes
    /// do not spread takes the other's; 1 cm where neither spreads).
    Eigen::Vector2f metresPerPixel{0.01f, 0.01f};
};

/// How the profile maps onto the canvas: a node at profile point q (across, up; m) is placed at
/// pixel + (q - profile) / metresPerPixel, up flipped to the canvas's y down. The schematic
/// keeps one while nodes are dragged, so that a move rescales nothing (a node moved up from a
/// row of tanks at one height no longer stretches the height to the whole canvas).
struct SchematicFrame {
    int along = 0;                                 ///< as SchematicLayout::along
    Eigen::Vector2d profile{0, 0};                 ///< a profile point, m
    Eigen::Vector2f pixel{0, 0};                   ///< where it lies on the canvas
    Eigen::Vector2f metresPerPixel{0.01f, 0.01f};  ///< across and up
    bool operator==(const SchematicFrame&) const = default;
};

/// The frame that fits every node's box into the width x height canvas (the axis the nodes
/// spread over more across it).
SchematicFrame schematicFrame(const WaterGraph& graph, float width, float height,
                              const Eigen::Vector2f& box);
/// The nodes placed by `frame`, then pushed apart.
SchematicLayout schematicLayout(const WaterGraph& graph, const SchematicFrame& frame,
                                const Eigen::Vector2f& box);
/// schematicLayout in the frame that fits the graph now (schematicFrame).
SchematicLayout schematicLayout(const WaterGraph& graph, float width, float height,
                                const Eigen::Vector2f& box);

/// The box every node's label fits in whole (its name, or its id where it has none): the
/// largest label's `textSize` in pixels as drawn (wrapped by the caller) plus a margin each
/// side (kSchematicMargin), and at least `minimum`.
inline const Eigen::Vector2f kSchematicMargin{6.0f, 5.0f};
Eigen::Vector2f schematicBoxFor(const WaterGraph& graph,
                                const std::function<Eigen::Vector2f(const std::string&)>& textSize,
                                const Eigen::Vector2f& minimum);
/// The label a schematic box shows: the node's name, or its id.
const std::string& schematicLabel(const GraphNode& node);

/// Where a node dragged by `pixels` on the schematic (x right, y down) moves, object space:
/// across the profile along the layout's axis and up, at the layout's scale.
Eigen::Vector3d schematicDragOffset(const SchematicLayout& layout, const Eigen::Vector2f& pixels);

/// The node whose port (the dot at the middle of its box's right edge) lies within `radius`
/// of canvas point `p` (the last drawn first), or -1.
int schematicPortAt(const SchematicLayout& layout, const Eigen::Vector2f& p, float radius);

/// The node whose box holds canvas point `p` (the last drawn, on top, first), or -1.
int schematicNodeAt(const SchematicLayout& layout, const Eigen::Vector2f& p);

}  // namespace plimsoll::editor
