// The viewport camera: an orbit camera around a target (Blender-like), its view presets and the
// matrices OpenGL uses. No GL here: tests use it to say where a point lands on the screen.
#pragma once

#include "plimsoll/geometry/mesh.h"

#include <Eigen/Core>

#include <optional>
#include <string>

namespace plimsoll::editor {

enum class ViewPreset { Front, Side, Top, Persp };
std::optional<ViewPreset> parseViewPreset(const std::string& name);  ///< front|side|top|persp

struct Camera {
    Eigen::Vector3d target = Eigen::Vector3d::Zero();  ///< orbit centre, world, m
    double yaw = 0.0;                  ///< rad about +y; 0: the camera sits on +z looking toward -z
    double pitch = 0.0;                ///< rad; positive: the camera is above, looking down
    double distance = 3.0;             ///< m from the target
    double fovY = 0.7853981633974483;  ///< rad, vertical (orthographic: sets the visible height)
    bool orthographic = false;

    Eigen::Vector3d eye() const;
    Eigen::Vector3d forward() const;  ///< unit, from the eye toward the target
    Eigen::Vector3d right() const;    ///< unit, screen right
    Eigen::Vector3d up() const;       ///< unit, screen up
    double nearPlane() const { return distance * 0.01; }
    double farPlane() const { return distance * 100.0; }

    Eigen::Matrix4d view() const;
    Eigen::Matrix4d projection(double aspect) const;

    /// Pixel position (x right, y down, origin at the image's top-left corner, pixel centres at
    /// half-integers) of a world point in a width x height image; nothing when behind the camera.
    std::optional<Eigen::Vector2d> toPixel(const Eigen::Vector3d& world, int width,
                                           int height) const;
    /// The ray through pixel position (x, y): origin and unit direction, world.
    void rayThrough(double x, double y, int width, int height, Eigen::Vector3d& origin,
                    Eigen::Vector3d& direction) const;

    // Navigation, in screen fractions (dx, dy of a mouse move divided by the viewport height).
    void orbit(double dx, double dy);
    void pan(double dx, double dy);
    void zoom(double steps);  ///< positive: closer

    /// Looks at the bounds' centre from far enough to see all of them.
    void frame(const Bounds3& bounds);
    /// front (+z, ortho), side (+x, ortho), top (+y, ortho), persp (from front-right, above).
    static Camera preset(ViewPreset view, const Bounds3& bounds);
};

/// What the view shows, as the 3D view's label says it: "Front (orthographic)", "Perspective".
const char* viewName(const Camera& camera);

}  // namespace plimsoll::editor
