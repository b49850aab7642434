// Exact area of the intersection of two UV triangles (Sutherland-Hodgman; both are convex):
// what the overlap check of validation and the physics-atlas charts measure overlap with.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>

namespace plimsoll::uvclip {

using Point2 = Eigen::Vector2d;

// Twice the signed area of (a, b, c): > 0 when c lies left of the line a -> b.
inline double orient(const Point2& a, const Point2& b, const Point2& c) {
    const Point2 ab = b - a, ac = c - a;
    return ab.x() * ac.y() - ab.y() * ac.x();
}

// In exact arithmetic a triangle clipped by three half-planes gains at most one vertex per
// plane. In floating point it can gain more: where corners lie within rounding of a clip line
// (degenerate or nearly collinear triangles), the orientation signs along the polygon can change
// more than twice, and each crossing adds a vertex. One clip emits at most two points per input
// vertex (the vertex and one crossing), so three clips of a triangle stay within 3 * 2^3.
struct ClipPolygon {
    static constexpr int kCapacity = 24;
    std::array<Point2, kCapacity> points;
    int size = 0;
    void push(const Point2& p) { points[static_cast<std::size_t>(size++)] = p; }
};

// Keeps the part of `polygon` left of the directed line a -> b.
inline ClipPolygon clipLeftOf(const ClipPolygon& polygon, const Point2& a, const Point2& b) {
    ClipPolygon out;
    for (int i = 0; i < polygon.size; ++i) {
        const Point2& current = polygon.points[static_cast<std::size_t>(i)];
        const Point2& next = polygon.points[static_cast<std::size_t>((i + 1) % polygon.size)];
        const double dc = orient(a, b, current), dn = orient(a, b, next);
        if (dc >= 0) out.push(current);
        if ((dc > 0 && dn < 0) || (dc < 0 && dn > 0)) {
            out.push(current + (next - current) * (dc / (dc - dn)));
        }
    }
    return out;
}

inline double polygonArea(const ClipPolygon& polygon) {
    double twice = 0;
    for (int i = 0; i < polygon.size; ++i) {
        const Point2& p = polygon.points[static_cast<std::size_t>(i)];
        const Point2& q = polygon.points[static_cast<std::size_t>((i + 1) % polygon.size)];
        twice += p.x() * q.y() - p.y() * q.x();
    }
    return 0.5 * twice;
}

// A UV triangle in counter-clockwise order (mirrored ones are reversed: overlap does not
// depend on orientation) with its bounding box.
struct UvTriangle {
    std::array<Point2, 3> corners;
    Eigen::AlignedBox2d box;
};

inline double intersectionArea(const UvTriangle& subject, const UvTriangle& clip) {
    ClipPolygon polygon;
    for (const Point2& p : subject.corners) polygon.push(p);
    for (int k = 0; k < 3 && polygon.size >= 3; ++k) {
        polygon = clipLeftOf(polygon, clip.corners[static_cast<std::size_t>(k)],
                             clip.corners[static_cast<std::size_t>((k + 1) % 3)]);
    }
    return polygon.size >= 3 ? polygonArea(polygon) : 0.0;
}

}  // namespace plimsoll::uvclip
