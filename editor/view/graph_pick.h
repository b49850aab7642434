// Where a water graph is on the screen, without GL: the node and pipe shapes the 3D view draws
// (graph_draw.cpp uses the same sizes), the ray tests that pick them, the rectangle that
// box-selects them and the drag geometry that moves them (along an axis, on a plane, on the
// surface). Tests check this math headless; the window only feeds it mouse positions.
#pragma once

#include "view/camera.h"

#include "plimsoll/graph/graph.h"
#include "plimsoll/physics/pose.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace plimsoll::editor {

/// Radius (m) of the sphere holding `volume` m^3: a sphere node is drawn and picked at it.
double sphereRadiusOfVolume(double volume);

/// Height (m, 0..2r) of the water in a sphere of radius r holding `water` m^3 (a spherical
/// cap: V = pi h^2 (3r - h) / 3, solved by bisection): the level a node is drawn filled to.
double sphereCapHeight(double radius, double water);

struct GraphHit {
    std::size_t index = 0;  ///< node or pipe index
    double distance = 0;    ///< along the ray, m
};

/// The nearest node the world ray (origin, unit direction) hits: a sphere node at its
/// capacity's radius, a box node as its box (object axes), the body at `pose`.
std::optional<GraphHit> pickNode(const WaterGraph& graph, const Pose& pose,
                                 const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);

/// The nearest pipe passing within max(its radius, `tolerance`) of the ray.
std::optional<GraphHit> pickPipe(const WaterGraph& graph, const Pose& pose,
                                 const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                 double tolerance);

/// Nodes whose centre projects inside the pixel rectangle with corners (x0, y0), (x1, y1) (any
/// order) of a width x height view: box selection.
std::vector<std::size_t> nodesInRect(const WaterGraph& graph, const Pose& pose,
                                     const Camera& camera, int width, int height, double x0,
                                     double y0, double x1, double y1);

/// The point of the line through `anchor` along unit `axis` closest to the ray (an axis-
/// constrained drag); the anchor itself when the ray runs along the axis.
Eigen::Vector3d closestOnAxis(const Eigen::Vector3d& anchor, const Eigen::Vector3d& axis,
                              const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);

/// Where the ray meets the plane through `point` with normal `normal`; nothing when it runs
/// parallel or the plane is behind.
std::optional<Eigen::Vector3d> rayPlane(const Eigen::Vector3d& origin,
                                        const Eigen::Vector3d& direction,
                                        const Eigen::Vector3d& point,
                                        const Eigen::Vector3d& normal);

}  // namespace plimsoll::editor
