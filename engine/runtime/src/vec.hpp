// The runtime's public 3-vector (runtime.hpp, which must not include the evaluation core) and
// the core's plimsoll_eval::Vec3, which holds the arithmetic: conversions, and the operations
// the loader and the motion step apply to public vectors, done in the core's type.
#pragma once

#include "plimsoll_runtime/runtime.hpp"

#include "plimsoll_eval/vec.hpp"

namespace plimsoll_runtime {

inline plimsoll_eval::Vec3 toEval(const Vec3& v) { return {v.x, v.y, v.z}; }
inline Vec3 fromEval(const plimsoll_eval::Vec3& v) { return {v.x, v.y, v.z}; }

inline plimsoll_eval::Mat3 toEval(const double R[3][3]) {
    plimsoll_eval::Mat3 m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m.m[i][j] = R[i][j];
    return m;
}

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return fromEval(toEval(a) + toEval(b)); }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return fromEval(toEval(a) - toEval(b)); }
inline Vec3 operator-(const Vec3& a) { return fromEval(-toEval(a)); }
inline Vec3 operator*(double s, const Vec3& a) { return fromEval(s * toEval(a)); }
inline Vec3& operator+=(Vec3& a, const Vec3& b) { return a = a + b; }
inline Vec3& operator-=(Vec3& a, const Vec3& b) { return a = a - b; }
inline double dot(const Vec3& a, const Vec3& b) { return plimsoll_eval::dot(toEval(a), toEval(b)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return fromEval(plimsoll_eval::cross(toEval(a), toEval(b)));
}
inline double norm(const Vec3& a) { return plimsoll_eval::norm(toEval(a)); }
inline bool finite(const Vec3& v) { return plimsoll_eval::finite(toEval(v)); }
/// R v and R^T v.
inline Vec3 mul(const double R[3][3], const Vec3& v) { return fromEval(toEval(R) * toEval(v)); }
inline Vec3 mulT(const double R[3][3], const Vec3& v) {
    return fromEval(plimsoll_eval::transposeTimes(toEval(R), toEval(v)));
}

}  // namespace plimsoll_runtime
