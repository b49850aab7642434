#include "view/camera.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace plimsoll::editor {

std::optional<ViewPreset> parseViewPreset(const std::string& name) {
    if (name == "front") return ViewPreset::Front;
    if (name == "side") return ViewPreset::Side;
    if (name == "top") return ViewPreset::Top;
    if (name == "persp") return ViewPreset::Persp;
    return std::nullopt;
}

Eigen::Vector3d Camera::forward() const {
    return -Eigen::Vector3d(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                            std::cos(pitch) * std::cos(yaw));
}

Eigen::Vector3d Camera::eye() const { return target - distance * forward(); }

Eigen::Vector3d Camera::right() const { return {std::cos(yaw), 0.0, -std::sin(yaw)}; }

Eigen::Vector3d Camera::up() const { return right().cross(forward()).normalized(); }

Eigen::Matrix4d Camera::view() const {
    const Eigen::Vector3d r = right(), u = up(), f = forward(), e = eye();
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<1, 3>(0, 0) = r.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -r.dot(e);
    m(1, 3) = -u.dot(e);
    m(2, 3) = f.dot(e);
    return m;
}

Eigen::Matrix4d Camera::projection(double aspect) const {
    const double n = nearPlane(), f = farPlane();
    Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
    if (orthographic) {
        const double hh = distance * std::tan(fovY / 2), hw = hh * aspect;
        p(0, 0) = 1.0 / hw;
        p(1, 1) = 1.0 / hh;
        p(2, 2) = -2.0 / (f - n);
        p(2, 3) = -(f + n) / (f - n);
        p(3, 3) = 1.0;
    } else {
        const double t = 1.0 / std::tan(fovY / 2);
        p(0, 0) = t / aspect;
        p(1, 1) = t;
        p(2, 2) = (f + n) / (n - f);
        p(2, 3) = 2 * f * n / (n - f);
        p(3, 2) = -1.0;
    }
    return p;
}

std::optional<Eigen::Vector2d> Camera::toPixel(const Eigen::Vector3d& world, int width,
                                               int height) const {
    const Eigen::Vector4d clip = projection(double(width) / height) * view() * world.homogeneous();
    if (clip.w() <= 0) return std::nullopt;
    const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
    return Eigen::Vector2d((ndc.x() * 0.5 + 0.5) * width, (0.5 - ndc.y() * 0.5) * height);
}

void Camera::rayThrough(double x, double y, int width, int height, Eigen::Vector3d& origin,
                        Eigen::Vector3d& direction) const {
    const double aspect = double(width) / height;
    const double nx = 2.0 * x / width - 1.0, ny = 1.0 - 2.0 * y / height;
    const double hh = std::tan(fovY / 2);
    if (orthographic) {
        origin = eye() + right() * (nx * hh * distance * aspect) + up() * (ny * hh * distance);
        direction = forward();
    } else {
        origin = eye();
        direction = (forward() + right() * (nx * hh * aspect) + up() * (ny * hh)).normalized();
    }
}

void Camera::orbit(double dx, double dy) {
    yaw -= dx * 3.0;
    pitch = std::clamp(pitch + dy * 3.0, -1.5707, 1.5707);
}

void Camera::pan(double dx, double dy) {
    const double scale = 2.0 * distance * std::tan(fovY / 2);
    target += (-right() * dx + up() * dy) * scale;
}

void Camera::zoom(double steps) {
    distance = std::clamp(distance * std::pow(0.85, steps), 1e-3, 1e6);
}

void Camera::frame(const Bounds3& bounds) {
    if (bounds.min.x() > bounds.max.x()) return;
    target = bounds.center();
    const double radius = std::max(0.5 * bounds.diagonal(), 1e-3);
    distance = radius / std::sin(fovY / 2) * 1.1;
}

Camera Camera::preset(ViewPreset view, const Bounds3& bounds) {
    Camera c;
    switch (view) {
        case ViewPreset::Front:
            c.orthographic = true;
            break;
        case ViewPreset::Side:
            c.yaw = 1.5707963267948966;
            c.orthographic = true;
            break;
        case ViewPreset::Top:
            c.pitch = 1.5707963267948966;
            c.orthographic = true;
            break;
        case ViewPreset::Persp:
            c.yaw = 0.6;
            c.pitch = 0.45;
            break;
    }
    c.frame(bounds);
    return c;
}

const char* viewName(const Camera& c) {
    const double halfPi = 1.5707963267948966;
    if (!c.orthographic) return "Perspective";
    if (std::abs(c.pitch - halfPi) < 1e-6) return "Top (orthographic)";
    if (std::abs(c.pitch) < 1e-6 && std::abs(c.yaw) < 1e-6) return "Front (orthographic)";
    if (std::abs(c.pitch) < 1e-6 && std::abs(c.yaw - halfPi) < 1e-6) return "Side (orthographic)";
    return "User (orthographic)";
}

}  // namespace plimsoll::editor
