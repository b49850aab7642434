// The fast evaluation's leaves (fast.hpp): the entries of the leaves left to per-entry work,
// evaluated one by one (entry.hpp's entryTerms and entryDrag, in single precision) into lanes
// of partial sums, in the body's axes.
#pragma once

#include "plimsoll_eval/entry.hpp"
#include "plimsoll_eval/fast_isa.hpp"
#include "plimsoll_eval/fast_tree.hpp"
#include "plimsoll_eval/vec.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace plimsoll_eval {

/// Consecutive leaves of kLanes entries (a tile's, or one leaf) left to per-entry work, with
/// their water in single precision: the surface's quadratic f + g.d + d^T H d / 2 (hxx, hzz
/// halved) about (cx, cz) relative to c, and the body's velocity relative to the water there
/// (in the body's axes, as the per-entry loops work: FloatRotation).
/// One record a tile rather than one a leaf: its leaves share the tile's water.
struct FastLeafWork {
    std::uint32_t begin = 0;
    std::uint32_t leaves = 1;
    float cx = 0, cz = 0, f = 0, gx = 0, gz = 0, hxx = 0, hxz = 0, hzz = 0;
    float ux = 0, uy = 0, uz = 0;
    /// The point of the call's velocity batch the relative velocity is taken at (-1: still
    /// water); u is filled in after the batch.
    std::int32_t slot = -1;
    /// An entry this far above the water (or more) adds nothing: half the largest entry's side,
    /// with a margin for rounding (perEntryLeaves skips leaves whose entries all are).
    float dryAbove = 0;
};

/// Per-entry sums of the leaves: each leaf's Lanes entries add into Lanes single-precision
/// lanes per sum (a loop without a carried dependency across entries, so that it vectorises);
/// the lanes go to double every kFlush leaves, so that a lane adds few terms in single precision
/// (32: a lane's sum to about 1e-6 of its terms' at worst, a few 1e-7 typically; the flush,
/// scalar code, every 8 leaves was a twentieth of a call on waves, and the measured errors did
/// not move past 1e-10 of their scales between 8 and 32).
template <int Slots, std::size_t Lanes>
struct LeafLaneSums {
    static constexpr std::size_t kFlush = 32;
    alignas(32) float lanes[Slots][Lanes] = {};
    double total[Slots] = {};
    void flush() {
        for (int slot = 0; slot < Slots; ++slot)
            for (std::size_t l = 0; l < Lanes; ++l) {
                total[slot] += lanes[slot][l];
                lanes[slot][l] = 0;
            }
    }
    /// After `leaves` more leaves, n of them done before.
    void leavesDone(std::size_t& n, std::size_t leaves) {
        const std::size_t before = n / kFlush;
        n += leaves;
        if (n / kFlush != before) flush();
    }
};

/// The body's rotation and its angular velocity in the body's own axes, in single precision,
/// for the per-entry loops. The loops work in the body's axes: an entry's forces and torques
/// and its velocity relative to the water need no rotation there (their sums are turned into
/// world axes once, after the loop), and only what the water decides (an entry's height, the
/// vertical part of its area vector) is taken in world axes.
struct FloatRotation {
    float R[3][3];
    float wx, wy, wz;
    FloatRotation(const Mat3& rotation, const Vec3& bodyAngular)
        : wx(static_cast<float>(bodyAngular.x)),
          wy(static_cast<float>(bodyAngular.y)),
          wz(static_cast<float>(bodyAngular.z)) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) R[i][j] = static_cast<float>(rotation.m[i][j]);
    }
    /// An entry's position in world axes (relative to c).
    void place(const float q[3], float r[3]) const {
        for (int m = 0; m < 3; ++m) r[m] = R[m][0] * q[0] + R[m][1] * q[1] + R[m][2] * q[2];
    }
    /// The vertical (world y) component of a vector given in the body's axes.
    float vertical(const float b[3]) const {
        return R[1][0] * b[0] + R[1][1] * b[1] + R[1][2] * b[2];
    }
    /// An entry's velocity relative to the water, body axes: u (the body's, at c, relative to
    /// the water; body axes) plus the spin's part at q.
    void velocity(float ux, float uy, float uz, const float q[3], float v[3]) const {
        v[0] = ux + wy * q[2] - wz * q[1];
        v[1] = uy + wz * q[0] - wx * q[2];
        v[2] = uz + wx * q[1] - wy * q[0];
    }
};

/// The per-entry sums' slots in LeafLaneSums: a vector's three components are consecutive.
struct EntrySlot {
    enum : int {
        volume = 0,
        moment = 1,
        pressureForce = 4,
        pressureTorque = 7,
        dragForce = 10,
        dragTorque = 13,
        wettedArea = 16,
        count = 17,
        slots = 18
    };
};
/// The per-entry drag's slots.
struct DragSlot {
    enum : int { force = 0, torque = 3, slots = 6 };
};

/// The vector in slots [first, first + 3) of a lane sum's totals.
inline Vec3 slotVector(const double* total, int first) {
    return Vec3{total[first], total[first + 1], total[first + 2]};
}

/// Calls leaf(record, columns) for every leaf of every record in turn, flushing the lanes of
/// `sums` (a LeafLaneSums) as the leaves add up, and last of all.
template <class LaneSums, class Leaf>
inline void forEachLeaf(const FastTree& tree, const std::vector<FastLeafWork>& records,
                        LaneSums& sums, Leaf leaf) {
    constexpr std::size_t kLanes = FastTree::kLanes;
    std::size_t done = 0;
    for (const FastLeafWork& w : records) {
        for (std::size_t first = w.begin; first < w.begin + w.leaves * kLanes; first += kLanes)
            leaf(w, tree.leafColumns(first));
        sums.leavesDone(done, w.leaves);
    }
    sums.flush();
}

/// The per-entry sums of every leaf in `leaves` (one pass, the call's constants set once), the
/// body turned by R and spinning at `angular` (world axes). SkipDry: leaves may come whole from
/// a tile (waves), and those clear of the water are skipped after a first pass over their
/// places.
template <bool Friction, bool SkipDry>
inline void perEntryLeaves(const FastTree& tree, const std::vector<FastLeafWork>& leaves,
                           const Mat3& R, const Vec3& angular, const Coefficients& k, Sums& sum) {
    const FloatRotation rotation(R, transposeTimes(R, angular));
    const float rhoG = static_cast<float>(k.rhoG), halfRhoCd = static_cast<float>(k.halfRhoCd),
                halfRhoCf = static_cast<float>(k.halfRhoCf);
    LeafLaneSums<EntrySlot::slots, FastTree::kLanes> sums;
    auto& lanes = sums.lanes;
    const double* total = sums.total;
    forEachLeaf(tree, leaves, sums,
                [&](const FastLeafWork& w, const FastTree::LeafColumns& column) {
                    const float *qx = column.qx, *qy = column.qy, *qz = column.qz, *bx = column.bx,
                                *by = column.by, *bz = column.bz, *area = column.area,
                                *inverseLength2 = column.inverseLength2,
                                *inverseLength = column.inverseLength, *valid = column.valid;
                    // The record's velocity held in registers, not read again for each entry.
                    const float ux = w.ux, uy = w.uy, uz = w.uz;
                    // First the entries' places and the water over them: a leaf whose entries are
                    // all clear above the water adds nothing (no depth, no wetted share) and is
                    // skipped. At the waterline of a tile on waves a quarter of the leaves are. (On
                    // flat water the leaves were sorted before: none comes here dry, and one pass
                    // is faster.)
                    auto waterAt = [&](const float q[3], float r[3]) {
                        rotation.place(q, r);
                        const float dx = r[0] - w.cx, dz = r[2] - w.cz;
                        return w.f + w.gx * dx + w.gz * dz + w.hxx * dx * dx + w.hxz * dx * dz +
                               w.hzz * dz * dz;
                    };
                    alignas(32) float rx[FastTree::kLanes], ry[FastTree::kLanes],
                        rz[FastTree::kLanes], height[FastTree::kLanes];
                    if constexpr (SkipDry) {
                        int wet = 0;
                        for (std::size_t i = 0; i < FastTree::kLanes; ++i) {
                            const float q[3] = {qx[i], qy[i], qz[i]};
                            float r[3];
                            height[i] = waterAt(q, r);
                            rx[i] = r[0];
                            ry[i] = r[1];
                            rz[i] = r[2];
                            wet |= r[1] - height[i] < w.dryAbove ? 1 : 0;
                        }
                        if (wet == 0) return;
                    }
                    for (std::size_t i = 0; i < FastTree::kLanes; ++i) {
                        float r[3], f;
                        if constexpr (SkipDry) {
                            r[0] = rx[i];
                            r[1] = ry[i];
                            r[2] = rz[i];
                            f = height[i];
                        } else {
                            const float q[3] = {qx[i], qy[i], qz[i]};
                            f = waterAt(q, r);
                        }
                        const float q[3] = {qx[i], qy[i], qz[i]}, b[3] = {bx[i], by[i], bz[i]};
                        float v[3];
                        rotation.velocity(ux, uy, uz, q, v);
                        // Depth, volume and moments in world axes; forces and torques in the
                        // body's.
                        const EntryTerms<float> e = entryTerms<float, Friction>(
                            r, rotation.vertical(b), q, b, area[i], inverseLength2[i],
                            inverseLength[i], f, v, rhoG, halfRhoCd, halfRhoCf);
                        lanes[EntrySlot::volume][i] += e.volume;
                        for (int m = 0; m < 3; ++m) {
                            lanes[EntrySlot::moment + m][i] += e.moment[m];
                            lanes[EntrySlot::pressureForce + m][i] += e.pressureForce[m];
                            lanes[EntrySlot::pressureTorque + m][i] += e.pressureTorque[m];
                            lanes[EntrySlot::dragForce + m][i] += e.dragForce[m];
                            lanes[EntrySlot::dragTorque + m][i] += e.dragTorque[m];
                        }
                        lanes[EntrySlot::wettedArea][i] += e.wettedArea;
                        lanes[EntrySlot::count][i] += valid[i] * e.count;
                    }
                });
    sum.volume += total[EntrySlot::volume];
    sum.moment += slotVector(total, EntrySlot::moment);
    sum.pressureForce += R * slotVector(total, EntrySlot::pressureForce);
    sum.pressureTorque += R * slotVector(total, EntrySlot::pressureTorque);
    sum.dragForce += R * slotVector(total, EntrySlot::dragForce);
    sum.dragTorque += R * slotVector(total, EntrySlot::dragTorque);
    sum.wettedArea += total[EntrySlot::wettedArea];
    sum.count += total[EntrySlot::count];
}

/// The drag of every leaf in `leaves`, all of whose entries are wholly wet.
template <bool Friction>
inline void dragLeaves(const FastTree& tree, const std::vector<FastLeafWork>& leaves, const Mat3& R,
                       const Vec3& angular, const Coefficients& k, Sums& sum) {
    // All in the body's axes (FloatRotation): no entry is rotated.
    const FloatRotation rotation(R, transposeTimes(R, angular));
    const float halfRhoCd = static_cast<float>(k.halfRhoCd),
                halfRhoCf = static_cast<float>(k.halfRhoCf);
    LeafLaneSums<DragSlot::slots, FastTree::kLanes> sums;
    auto& lanes = sums.lanes;
    const double* total = sums.total;
    forEachLeaf(tree, leaves, sums,
                [&](const FastLeafWork& w, const FastTree::LeafColumns& column) {
                    const float *qx = column.qx, *qy = column.qy, *qz = column.qz, *bx = column.bx,
                                *by = column.by, *bz = column.bz, *area = column.area,
                                *inverseLength = column.inverseLength, *valid = column.valid;
                    // The record's velocity held in registers, not read again for each entry.
                    const float ux = w.ux, uy = w.uy, uz = w.uz;
                    for (std::size_t i = 0; i < FastTree::kLanes; ++i) {
                        const float q[3] = {qx[i], qy[i], qz[i]};
                        const float b[3] = {bx[i], by[i], bz[i]};
                        float v[3];
                        rotation.velocity(ux, uy, uz, q, v);
                        float force[3], torque[3];
                        entryDrag<float, Friction>(q, b, area[i], inverseLength[i], valid[i], v,
                                                   halfRhoCd, halfRhoCf, force, torque);
                        for (int m = 0; m < 3; ++m) {
                            lanes[DragSlot::force + m][i] += force[m];
                            lanes[DragSlot::torque + m][i] += torque[m];
                        }
                    }
                });
    sum.dragForce += R * slotVector(total, DragSlot::force);
    sum.dragTorque += R * slotVector(total, DragSlot::torque);
}

#ifdef PLIMSOLL_EVAL_AVX2_LOOPS
template <bool Friction, bool SkipDry>
PLIMSOLL_EVAL_AVX2_TARGET void perEntryLeavesAvx2(const FastTree& tree,
                                                  const std::vector<FastLeafWork>& leaves,
                                                  const Mat3& R, const Vec3& angular,
                                                  const Coefficients& k, Sums& sum) {
    perEntryLeaves<Friction, SkipDry>(tree, leaves, R, angular, k, sum);
}
template <bool Friction>
PLIMSOLL_EVAL_AVX2_TARGET void dragLeavesAvx2(const FastTree& tree,
                                              const std::vector<FastLeafWork>& leaves,
                                              const Mat3& R, const Vec3& angular,
                                              const Coefficients& k, Sums& sum) {
    dragLeaves<Friction>(tree, leaves, R, angular, k, sum);
}
#endif

/// perEntryLeaves for the call's friction and skipDry, on the instruction set that runs
/// (fast_isa.hpp).
inline void perEntrySums(const FastTree& tree, const std::vector<FastLeafWork>& leaves,
                         const Mat3& R, const Vec3& angular, const Coefficients& k, bool skipDry,
                         Sums& sum) {
    if (leaves.empty()) return;
    withFlag(k.halfRhoCf > 0, [&](auto friction) {
        withFlag(skipDry, [&](auto skip) {
            constexpr bool Friction = decltype(friction)::value, SkipDry = decltype(skip)::value;
#ifdef PLIMSOLL_EVAL_AVX2_LOOPS
            if (cpuHasAvx2Fma())
                return perEntryLeavesAvx2<Friction, SkipDry>(tree, leaves, R, angular, k, sum);
#endif
            perEntryLeaves<Friction, SkipDry>(tree, leaves, R, angular, k, sum);
        });
    });
}

/// dragLeaves for the call's friction, on the instruction set that runs.
inline void dragPerEntrySums(const FastTree& tree, const std::vector<FastLeafWork>& leaves,
                             const Mat3& R, const Vec3& angular, const Coefficients& k, Sums& sum) {
    if (leaves.empty()) return;
    withFlag(k.halfRhoCf > 0, [&](auto friction) {
        constexpr bool Friction = decltype(friction)::value;
#ifdef PLIMSOLL_EVAL_AVX2_LOOPS
        if (cpuHasAvx2Fma()) return dragLeavesAvx2<Friction>(tree, leaves, R, angular, k, sum);
#endif
        dragLeaves<Friction>(tree, leaves, R, angular, k, sum);
    });
}

}  // namespace plimsoll_eval
