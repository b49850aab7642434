#include "view/graph_pick.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

namespace plimsoll::editor {

double sphereRadiusOfVolume(double volume) {
    return std::cbrt(3.0 * std::max(volume, 0.0) / (4.0 * std::numbers::pi));
}

double sphereCapHeight(double radius, double water) {
    const double full = 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
    if (water <= 0 || radius <= 0) return 0;
    if (water >= full) return 2 * radius;
    double lo = 0, hi = 2 * radius;
    for (int i = 0; i < 60; ++i) {  // the cap volume rises monotonically with h
        const double h = 0.5 * (lo + hi);
        const double v = std::numbers::pi * h * h * (3 * radius - h) / 3.0;
        (v < water ? lo : hi) = h;
    }
    return 0.5 * (lo + hi);
}

namespace {

/// Distance along the ray to a sphere, or nothing (a ray starting inside hits at 0).
std::optional<double> raySphere(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                const Eigen::Vector3d& c, double r) {
    const Eigen::Vector3d oc = o - c;
    const double b = oc.dot(d), cc = oc.squaredNorm() - r * r;
    if (cc <= 0) return 0.0;
    const double disc = b * b - cc;
    if (disc < 0) return std::nullopt;
    const double t = -b - std::sqrt(disc);
    if (t < 0) return std::nullopt;
    return t;
}

/// Slab test against the axis-aligned box centre c, edge lengths size.
std::optional<double> rayBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                             const Eigen::Vector3d& c, const Eigen::Vector3d& size) {
    double t0 = 0, t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const double lo = c[k] - size[k] / 2, hi = c[k] + size[k] / 2;
        if (std::abs(d[k]) < 1e-300) {
            if (o[k] < lo || o[k] > hi) return std::nullopt;
            continue;
        }
        double a = (lo - o[k]) / d[k], b = (hi - o[k]) / d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return std::nullopt;
    }
    return t0;
}

/// The ray in object space (a rigid pose keeps distances along it).
void toObject(const Pose& pose, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
              Eigen::Vector3d& o, Eigen::Vector3d& d) {
    o = pose.rotation.transpose() * (origin - pose.translation);
    d = pose.rotation.transpose() * direction;
}

}  // namespace

std::optional<GraphHit> pickNode(const WaterGraph& graph, const Pose& pose,
                                 const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
    Eigen::Vector3d o, d;
    toObject(pose, origin, direction, o, d);
    std::optional<GraphHit> best;
    for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
        const GraphNode& n = graph.nodes[i];
        const std::optional<double> t =
            n.isBox() ? rayBox(o, d, n.position, n.boxSize)
                      : raySphere(o, d, n.position, sphereRadiusOfVolume(n.capacity));
        if (t && (!best || *t < best->distance)) best = GraphHit{i, *t};
    }
    return best;
}

std::optional<GraphHit> pickPipe(const WaterGraph& graph, const Pose& pose,
                                 const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                 double tolerance) {
    Eigen::Vector3d o, d;
    toObject(pose, origin, direction, o, d);
    std::optional<GraphHit> best;
    // Pipe ends by hash: indexOf scans the nodes, and a frame drew every pipe.
    std::unordered_map<std::string, int> indexById;
    for (std::size_t n = 0; n < graph.nodes.size(); ++n)
        indexById.emplace(graph.nodes[n].id, static_cast<int>(n));
    for (std::size_t i = 0; i < graph.pipes.size(); ++i) {
        const auto ia = indexById.find(graph.pipes[i].a), ib = indexById.find(graph.pipes[i].b);
        if (ia == indexById.end() || ib == indexById.end()) continue;
        const int a = ia->second, b = ib->second;
        const Eigen::Vector3d p = graph.nodes[a].position, q = graph.nodes[b].position;
        // Closest points of the ray o + t d (t >= 0) and the segment p + s (q - p), s in 0..1.
        const Eigen::Vector3d u = q - p, w = o - p;
        const double uu = u.dot(u), ud = u.dot(d), uw = u.dot(w), dw = d.dot(w);
        const double denom = uu - ud * ud;  // |d| = 1
        double s = denom > 1e-300 ? (uw - ud * dw) / denom : 0.0;
        s = std::clamp(s, 0.0, 1.0);
        const double t = std::max(0.0, (p + s * u - o).dot(d));
        const double gap = (o + t * d - (p + s * u)).norm();
        if (gap <= std::max(graph.pipes[i].radius, tolerance) && (!best || t < best->distance)) {
            best = GraphHit{i, t};
        }
    }
    return best;
}

std::vector<std::size_t> nodesInRect(const WaterGraph& graph, const Pose& pose,
                                     const Camera& camera, int width, int height, double x0,
                                     double y0, double x1, double y1) {
    const double left = std::min(x0, x1), right = std::max(x0, x1);
    const double top = std::min(y0, y1), bottom = std::max(y0, y1);
    std::vector<std::size_t> inside;
    for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
        const auto pixel = camera.toPixel(pose.apply(graph.nodes[i].position), width, height);
        if (pixel && pixel->x() >= left && pixel->x() <= right && pixel->y() >= top &&
            pixel->y() <= bottom) {
            inside.push_back(i);
        }
    }
    return inside;
}

Eigen::Vector3d closestOnAxis(const Eigen::Vector3d& anchor, const Eigen::Vector3d& axis,
                              const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
    // Lines anchor + s axis and origin + t direction: minimise the gap over s and t.
    const Eigen::Vector3d w = anchor - origin;
    const double ad = axis.dot(direction), denom = 1.0 - ad * ad;
    if (denom < 1e-9) return anchor;
    const double s = (ad * direction.dot(w) - axis.dot(w)) / denom;
    return anchor + s * axis;
}

std::optional<Eigen::Vector3d> rayPlane(const Eigen::Vector3d& origin,
                                        const Eigen::Vector3d& direction,
                                        const Eigen::Vector3d& point,
                                        const Eigen::Vector3d& normal) {
    const double dn = direction.dot(normal);
    if (std::abs(dn) < 1e-12) return std::nullopt;
    const double t = (point - origin).dot(normal) / dn;
    if (t < 0) return std::nullopt;
    return origin + t * direction;
}

}  // namespace plimsoll::editor
