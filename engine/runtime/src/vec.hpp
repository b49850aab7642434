// Internal 3-vector helpers (the runtime has no linear-algebra dependency).
#pragma once

#include "plimsoll_runtime/runtime.hpp"

#include <cmath>

namespace plimsoll_runtime {

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a.x, s * a.y, s * a.z}; }
inline Vec3& operator+=(Vec3& a, const Vec3& b) {
    a.x += b.x;
    a.y += b.y;
    a.z += b.z;
    return a;
}
inline Vec3& operator-=(Vec3& a, const Vec3& b) {
    a.x -= b.x;
    a.y -= b.y;
    a.z -= b.z;
    return a;
}
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 mul(const double R[3][3], const Vec3& v) {
    return {R[0][0] * v.x + R[0][1] * v.y + R[0][2] * v.z,
            R[1][0] * v.x + R[1][1] * v.y + R[1][2] * v.z,
            R[2][0] * v.x + R[2][1] * v.y + R[2][2] * v.z};
}
/// R^T v.
inline Vec3 mulT(const double R[3][3], const Vec3& v) {
    return {R[0][0] * v.x + R[1][0] * v.y + R[2][0] * v.z,
            R[0][1] * v.x + R[1][1] * v.y + R[2][1] * v.z,
            R[0][2] * v.x + R[1][2] * v.y + R[2][2] * v.z};
}
inline bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace plimsoll_runtime
