// What the 3D view shows of a water graph on the hull, GL-free: a colour per node, the
// surface coloured by the node each texel feeds (texelNodeMap, paper 4.2) and by the segment
// of an automatic segmentation (its preview before "Apply"), as overlay images over the
// physics texture (overlay.h).
#pragma once

#include "document/overlay.h"

#include "plimsoll/bake.h"
#include "plimsoll/graph.h"

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

}  // namespace plimsoll::editor
