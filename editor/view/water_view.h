// The water as the 3D view shows it, without drawing a surface: a translucent sheet over what
// lies beyond it is the same as tinting, pixel by pixel, whatever the eye sees through the
// water. So the view's background is split at the horizon into a tinted half and a plain one
// (two rectangles: the larger one is the frame's whole-window clear, which costs llvmpipe
// next to nothing), and the bodies, grid and water graph tint their own fragments that lie
// across the water from the eye. On llvmpipe a surface drawn over the buoy preview's view
// (about 900k pixels) cost 5 ms of a 21 ms frame.
//
// This is the C++ twin of render/shaders/water_view.vert and .frag: the same heights, the same
// triangles between them and the same test, for the background split and for tests. The
// shaders take the test's two depths at the vertices and interpolate them across a triangle
// (per fragment, six fetches of the heights cost llvmpipe more than the sheet this replaces):
// exact on flat water and at the vertices; on waves, where a triangle spans a bend of the
// surface, the drawn waterline may stand off the twin's by the bend's height over the
// triangle (lines are drawn in pieces of at most a cell, so that it is at most one cell's).
#pragma once

#include "view/camera.h"

#include "plimsoll/physics/water.h"

#include <Eigen/Core>

#include <vector>

namespace plimsoll::editor {

class WaterView {
public:
    /// Heights sampled on a square grid of `kCells` cells a side around the camera's target,
    /// out to 3 camera distances (at least 10 m): a 4 m wave still gets six samples at the
    /// closest zoom. Outside the square the water keeps the heights of its edge.
    static constexpr int kCells = 32;
    static WaterView of(const WaterModel& water, double time, const Camera& camera);

    /// The surface's height at (x, z): linear over the two triangles of each grid cell, split
    /// along the cell's diagonal from (i, j) to (i + 1, j + 1).
    double heightAt(double x, double z) const;
    bool below(const Eigen::Vector3d& p) const { return p.y() < heightAt(p.x(), p.z()); }
    /// Whether the eye sees point p through the water: p and the eye's end of its line of sight
    /// (the eye, or for an orthographic view the point's foot on the plane through the eye)
    /// lie on opposite sides of the surface.
    bool seenThrough(const Eigen::Vector3d& p) const;
    /// Whether the background seen along the ray from `origin` (on the eye's side of the
    /// view) in `direction` is seen through the water: the ray starts above the water and goes
    /// down, or starts below it and goes up (the water reaches the horizon).
    bool backgroundSeenThrough(const Eigen::Vector3d& origin,
                               const Eigen::Vector3d& direction) const;
    /// The view's background in a width x height image: rows [0, split) from the top show
    /// `top` (seen through the water or not), rows [split, height) the other. The camera has
    /// no roll, so each row is one or the other (split = height: one colour throughout).
    struct Backdrop {
        int split = 0;
        bool topSeenThrough = false;
        int height = 0;
        /// The larger part (the one a caller clears the whole image to) and the other part's
        /// rows, counted from the top (none when the image is all one part).
        bool largerTop() const { return 2 * split >= height; }
        bool largerSeenThrough() const { return largerTop() == topSeenThrough; }
        int smallerFirstRow() const { return largerTop() ? split : 0; }
        int smallerRows() const { return largerTop() ? height - split : split; }
    };
    Backdrop backdrop(int width, int height) const;

    /// The surface drawn as a net on waves (Renderer): the samples joined to their
    /// neighbours along x and along z, two points a segment, each at its sample's height (the
    /// water model's height there). `lift` moves every point up by that much (m): the
    /// renderer lifts the net a millimetre toward the eye, so that the tint test sees it on
    /// the eye's side of the surface it lies on.
    std::vector<Eigen::Vector3f> surfaceSegments(float lift = 0.0f) const;
    /// The same into `points` (its storage reused: the renderer calls this every frame).
    void surfaceSegments(float lift, std::vector<Eigen::Vector3f>& points) const;

    /// The samples, row j (along z) after row j - 1, kCells + 1 to a row, from (x0, z0) in
    /// steps of `step` m.
    std::vector<float> heights;
    double x0 = 0, z0 = 0, step = 1;
    Camera camera;
};

/// `colour` as seen through water of colour `water` and opacity `alpha` (a sheet over it).
inline Eigen::Vector3f throughWater(const Eigen::Vector3f& colour, const Eigen::Vector3f& water,
                                    float alpha) {
    return colour + alpha * (water - colour);
}

}  // namespace plimsoll::editor
