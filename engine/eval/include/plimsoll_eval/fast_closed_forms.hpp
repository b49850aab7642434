// The fast evaluation's closed forms (fast.hpp): the sums of entries that are all wholly wet
// under one water quadratic, or that all face one flow, as polynomials of their moments
// (fast_tree.hpp's FastMoments). Closed forms are linear in the moments, so nodes that share
// one polynomial add their moments and the polynomial is evaluated once (docs/fast-path.md).
#pragma once

#include "plimsoll_eval/entry.hpp"
#include "plimsoll_eval/fast_tree.hpp"
#include "plimsoll_eval/vec.hpp"

#include <algorithm>
#include <cmath>

namespace plimsoll_eval {

/// What the hydrostatic sums need of wholly wet entries under a water quadratic: with the depth
/// (object axes) d(s) = alpha + beta.s + s^T H s / 2 about a point p (s = q - p),
///   d0 = sum d b,   d1 = sum d b q^T (about c),   e = sum d^2 b less sum (s^T H s)^2 b / 4,
/// the one term the moments do not reach (fourth order; of the order of the curvature's squared
/// departure over the entries, smallest about a point among them: FastBody::evaluate takes p
/// above the stencil's grid node at the mean height of its nodes' centres).
struct FastDepthIntegrals {
    double d0[3] = {};
    double d1[3][3] = {};
    double e[3] = {};
};

/// The water's Hessian in object axes, R^T H3 R, H3 the horizontal Hessian (hxx, hxz, hzz) in
/// world axes: its y row and column are zero, so only the x and z rows of R enter.
inline void objectHessian(const Mat3& R, double hxx, double hxz, double hzz, double H[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            H[i][j] = R.m[0][i] * hxx * R.m[0][j] + R.m[0][i] * hxz * R.m[2][j] +
                      R.m[2][i] * hxz * R.m[0][j] + R.m[2][i] * hzz * R.m[2][j];
}

/// The depth integrals of entries whose moments about c are m (orders 0 to 2, and 3 where H is
/// not zero). d0 and d1 take the depth expanded about c, where it is the same quadratic with
///   alpha' = alpha - beta.p + p^T H p / 2,   beta' = beta - H p,
/// so that they are exact in the moments about c without shifting them. e is taken about p (its
/// left-out term is smallest there), its moments about p written through those about c:
///   e = alpha^2 n0 + 2 alpha (n1 beta)' + (beta n2 beta)' + alpha (n2:H)' + (beta.(n3:H))'
///   (n1 beta)'      = n1 beta - n0 (p.beta)
///   (beta n2 beta)' = beta n2 beta - 2 (n1 beta)(p.beta) + n0 (p.beta)^2
///   (n2:H)'         = n2:H - 2 n1 Hp + n0 pHp
///   (beta.(n3:H))'  = beta.(n3:H) - 2 beta.(n2 Hp) - (p.beta)(n2:H) + (n1 beta) pHp
///                     + 2 (p.beta)(n1 Hp) - n0 (p.beta) pHp
/// (the contraction with beta of n3 shifted by p, its terms the binomial expansion of
/// (s + p)(s + p)(s + p) against H). One pass over the moments: what a stencil's bucket costs.
inline FastDepthIntegrals depthIntegrals(const FastMoments& m, const Vec3& p, double alpha,
                                         const Vec3& beta, const double H[3][3]) {
    bool curved = false;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) curved = curved || H[i][j] != 0;
    const double pv[3] = {p.x, p.y, p.z}, bv[3] = {beta.x, beta.y, beta.z};
    double Hp[3] = {}, pHp = 0;
    // H packed as kPair's slots, its off-diagonal terms doubled: n:H over 6 slots, not 9.
    double Hs[6] = {};
    if (curved) {
        for (int l = 0; l < 3; ++l) Hp[l] = H[l][0] * pv[0] + H[l][1] * pv[1] + H[l][2] * pv[2];
        pHp = pv[0] * Hp[0] + pv[1] * Hp[1] + pv[2] * Hp[2];
        for (int j = 0; j < 3; ++j)
            for (int l = j; l < 3; ++l) Hs[kPair[j][l]] = (j == l ? 1.0 : 2.0) * H[j][l];
    }
    const double pb = pv[0] * bv[0] + pv[1] * bv[1] + pv[2] * bv[2];
    const double alphaC = alpha - pb + 0.5 * pHp;
    FastDepthIntegrals out;
    for (int u = 0; u < 3; ++u) {
        const double n0 = m.n0[u];
        double n1b = 0, n1Hp = 0, n2H = 0, n2bb = 0, n2bHp = 0, bn3H = 0;
        double n2b[3], n2Hp[3] = {}, n3H[3] = {};
        for (int j = 0; j < 3; ++j) {
            n1b += m.n1[u][j] * bv[j];
            n2b[j] = m.n2[u][kPair[j][0]] * bv[0] + m.n2[u][kPair[j][1]] * bv[1] +
                     m.n2[u][kPair[j][2]] * bv[2];
            n2bb += n2b[j] * bv[j];
        }
        if (curved) {
            for (int j = 0; j < 3; ++j) {
                n1Hp += m.n1[u][j] * Hp[j];
                n2Hp[j] = m.n2[u][kPair[j][0]] * Hp[0] + m.n2[u][kPair[j][1]] * Hp[1] +
                          m.n2[u][kPair[j][2]] * Hp[2];
                n2bHp += bv[j] * n2Hp[j];
                double c = 0;
                for (int l = 0; l < 6; ++l)
                    c += m.n3[u][kTriple[j][kPairFirst[l]][kPairSecond[l]]] * Hs[l];
                n3H[j] = c;
                bn3H += bv[j] * c;
            }
            for (int l = 0; l < 6; ++l) n2H += m.n2[u][l] * Hs[l];
        }
        out.d0[u] = alphaC * n0 + n1b - n1Hp + 0.5 * n2H;
        for (int j = 0; j < 3; ++j)
            out.d1[u][j] = alphaC * m.n1[u][j] + n2b[j] - n2Hp[j] + 0.5 * n3H[j];
        const double n1bP = n1b - n0 * pb;
        const double n2bbP = n2bb - 2 * n1b * pb + n0 * pb * pb;
        const double n2HP = n2H - 2 * n1Hp + n0 * pHp;
        const double bn3HP =
            bn3H - 2 * n2bHp - pb * n2H + n1b * pHp + 2 * pb * n1Hp - n0 * pb * pHp;
        out.e[u] = alpha * alpha * n0 + 2 * alpha * n1bP + n2bbP + alpha * n2HP + bn3HP;
    }
    return out;
}

/// How the entries of node t meet the flow (object axes: uo the body's velocity relative to
/// the water at c, wo its spin, spinRate = |wo|): all turned away (no pressure drag), all
/// facing it (the drag is a polynomial of their moments), or mixed (its children decide).
enum class FastDragSign { away, facing, mixed };

/// FastDragSign of node t, whose normals' cone has sine `sinSpread`.
inline FastDragSign dragSign(const FastTile& t, double sinSpread, const Vec3& uo, const Vec3& wo,
                             double spinRate, const Coefficients& k) {
    if (k.halfRhoCf > 0) return FastDragSign::mixed;  // skin friction has no polynomial form
    // t_i = b_i.v_i with v_i = vc + wo x s_i (vc the velocity at the node's centre): its sign
    // over the node from the normal cone against vc, widened by the spin over the radius.
    const Vec3 vc = uo + cross(wo, t.center);
    const double speed2 = dot(vc, vc);
    const double spread = spinRate * t.radius;
    if (speed2 == 0 && spread == 0) return FastDragSign::away;  // at rest in still water: no drag
    // The largest and smallest component of the flow along a normal of the cone: with phi the
    // flow's angle from the axis and theta the cone's half-angle, V cos(phi - theta) (V itself
    // where phi <= theta) and V cos(phi + theta) (-V where phi + theta >= pi), V = |vc|. With
    // along = V cos(phi) and across = V sin(phi) they are along c +- across s (c, s the cosine
    // and sine of theta), compared squared: no square root (three were a fifth of the drag's
    // traversal).
    const double c = t.cosSpread, along = dot(t.axis, vc);
    const double across2 = std::max(0.0, speed2 - along * along), s2 = sinSpread * sinSpread;
    // x >= V y, V known only squared.
    auto atLeastSpeedTimes = [&](double x, double y) {
        return y >= 0 ? x >= 0 && x * x >= speed2 * y * y : x >= 0 || x * x <= speed2 * y * y;
    };
    // Away: the largest component at most -spread (never where the flow is inside the cone).
    if (!atLeastSpeedTimes(along, c)) {
        const double room = -(spread + along * c);  // -spread - along c >= across s
        if (room >= 0 && across2 * s2 <= room * room) return FastDragSign::away;
    }
    // Facing: the smallest above spread (never where the flow is against the cone).
    if (!atLeastSpeedTimes(-along, c)) {
        const double room = along * c - spread;  // along c - spread > across s
        if (room > 0 && room * room > across2 * s2) return FastDragSign::facing;
    }
    return FastDragSign::mixed;
}

/// The pressure drag of entries that all face the flow, from their moments about `center`
/// (object axes; torque about c).
inline void dragFromMoments(const FastMoments& mo, const Vec3& center, const Vec3& uo,
                            const Vec3& wo, const Coefficients& k, Vec3& force, Vec3& torque) {
    // Every entry faces the flow: D = -k sum (b.v) v with v = vc + wo x s, a polynomial in s
    // (file comment). b.(wo x s) = wo.(s x b), so a moment X[u][...] (u the area vector's axis,
    // the first index s's) contracts with the spin as spin(X) = wo.x (X[z][y] - X[y][z]) +
    // wo.y (X[x][z] - X[z][x]) + wo.z (X[y][x] - X[x][y]).
    const Vec3 vc = uo + cross(wo, center);
    const double v[3] = {vc.x, vc.y, vc.z};
    auto spin = [&](auto&& X) {
        return wo.x * (X(2, 1) - X(1, 2)) + wo.y * (X(0, 2) - X(2, 0)) + wo.z * (X(1, 0) - X(0, 1));
    };
    // sumT = sum b.v, St = sum (b.v) s, T = sum (b.v) s s^T (symmetric: its 6 slots).
    double sumT = mo.n0[0] * v[0] + mo.n0[1] * v[1] + mo.n0[2] * v[2] +
                  spin([&](int u, int j) { return mo.n1[u][j]; });
    double St[3], T[6];
    for (int l = 0; l < 3; ++l)
        St[l] = mo.n1[0][l] * v[0] + mo.n1[1][l] * v[1] + mo.n1[2][l] * v[2] +
                spin([&](int u, int j) { return mo.n2[u][kPair[j][l]]; });
    for (int slot = 0; slot < 6; ++slot) {
        const int l = kPairFirst[slot], n = kPairSecond[slot];
        T[slot] = mo.n2[0][slot] * v[0] + mo.n2[1][slot] * v[1] + mo.n2[2][slot] * v[2] +
                  spin([&](int u, int j) { return mo.n3[u][kTriple[j][l][n]]; });
    }
    const Vec3 st{St[0], St[1], St[2]};
    const Vec3 Tw{T[0] * wo.x + T[1] * wo.y + T[2] * wo.z, T[1] * wo.x + T[3] * wo.y + T[4] * wo.z,
                  T[2] * wo.x + T[4] * wo.y + T[5] * wo.z};
    const double trace = T[0] + T[3] + T[5];
    force = -k.halfRhoCd * (sumT * vc + cross(wo, st));
    // About `center`, then about c.
    torque = -k.halfRhoCd * (cross(st, vc) + trace * wo - Tw) + cross(center, force);
}

/// The hydrostatic sums of wholly wet entries from their depth integrals.
inline void hydrostaticsFromDepthIntegrals(const FastDepthIntegrals& in, const Mat3& R,
                                           const Coefficients& k, Sums& sum) {
    // The world's vertical is R's row y: the volume is -sum d b.y, the first moments -sum d b.y q
    // and, vertically, -sum (d q.y + d^2 / 2) b.y in world axes; pressure -rho g d b.
    const Vec3 rowY = R.row(1);
    const Vec3 d0{in.d0[0], in.d0[1], in.d0[2]};
    const Vec3 torque{in.d1[2][1] - in.d1[1][2], in.d1[0][2] - in.d1[2][0],
                      in.d1[1][0] - in.d1[0][1]};
    // rowY^T d1, then against each row of R.
    double y[3];
    for (int j = 0; j < 3; ++j)
        y[j] = rowY.x * in.d1[0][j] + rowY.y * in.d1[1][j] + rowY.z * in.d1[2][j];
    const Vec3 yD1{y[0], y[1], y[2]};
    sum.volume -= dot(rowY, d0);
    sum.moment.x -= dot(yD1, R.row(0));
    sum.moment.y -= dot(yD1, rowY) + 0.5 * dot(rowY, Vec3{in.e[0], in.e[1], in.e[2]});
    sum.moment.z -= dot(yD1, R.row(2));
    sum.pressureForce -= k.rhoG * (R * d0);
    sum.pressureTorque -= k.rhoG * (R * torque);
}

}  // namespace plimsoll_eval
