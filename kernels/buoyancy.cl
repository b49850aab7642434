// Per-frame buoyancy of a batch of bodies over their compacted texel entries.
// plimsoll_shared.h is prepended at build time; PL_ACC_DOUBLE is defined when the device has
// cl_khr_fp64. The C++ reference is engine/src/physics/buoyancy_reference.cpp (same formulas, double
// precision, no culling); tests hold this file against it.
//
// Launch 1, buoyancy_tiles_<water model>[_still]: one work-group per tile of up to
// PL_WORKGROUP_SIZE x PL_ITEMS_PER_THREAD entries ("_still": no drag, for bodies at rest in
// still water). A tile whose bounding sphere lies entirely above the highest possible water
// surface adds nothing and reads no texel (a floating body skips most of its dry half). Any
// other tile is placed against the water over it (exact on flat water; a quadratic sampled by
// the group on waves): dry, wholly wet (summed from its moments by one work-item), or at the
// waterline (buoyancyTiles). Each work-item accumulates its entries in float, then the group
// reduces all slots at once in local memory (reduceGroup) and writes one partial.
// Launch 2, reduce_chunks: one work-group per chunk of a body's tiles sums their partials; the
// host adds a body's chunks.

// Each work-item sums its few entries in float; the group's reduction and everything after it
// run in acc_t (double where the device has it), so a body of 8192^2 texels keeps 1e-6
// relative precision.
#ifdef PL_ACC_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double acc_t;
#else
typedef float acc_t;
#endif

#define PL_TWO_PI 6.283185307179586f

#define PL_INLINE inline __attribute__((always_inline))

PL_INLINE float3 rotateToWorld(const PlBody* body, float3 v) {
    return (float3)(dot(body->rotation[0].xyz, v), dot(body->rotation[1].xyz, v),
                    dot(body->rotation[2].xyz, v));
}

/// Undisplaced horizontal position of the Gerstner surface point above (x, z): three
/// fixed-point steps, as WaterModel::height does.
PL_INLINE float2 gerstnerUndisplaced(const PlBody* body, __global const PlWave* waves, float2 xz) {
    float2 x0 = xz;
    for (int iteration = 0; iteration < 3; ++iteration) {
        float2 shift = (float2)(0.0f, 0.0f);
        for (int w = 0; w < body->waveCount; ++w) {
            const PlWave wave = waves[body->waveBegin + w];
            const float2 d = (float2)(wave.directionX, wave.directionZ);
            const float theta = wave.wavenumber * dot(d, x0) + wave.phase;
            shift += wave.q * wave.amplitude * sin(theta) * d;
        }
        x0 = xz + shift;
    }
    return x0;
}

/// The Gerstner surface's height above (r.x, r.z) and the water's orbital velocity at r
/// (decaying below the mean level) with its derivative along y, from one solve for the
/// undisplaced point: the height and velocity of one entry, or of one sample of a tile's water.
PL_INLINE void gerstnerSample(const PlBody* body, __global const PlWave* waves, float3 r,
                              float* height, float3* velocity, float3* velocityDy) {
    const float2 x0 = gerstnerUndisplaced(body, waves, r.xz);
    float y = body->water.x;
    float3 u = (float3)(0.0f, 0.0f, 0.0f), dudy = (float3)(0.0f, 0.0f, 0.0f);
    const bool below = r.y < body->water.x;
    for (int w = 0; w < body->waveCount; ++w) {
        const PlWave wave = waves[body->waveBegin + w];
        const float2 d = (float2)(wave.directionX, wave.directionZ);
        const float theta = wave.wavenumber * dot(d, x0) + wave.phase;
        float cosTheta;
        const float sinTheta = sincos(theta, &cosTheta);
        y += wave.amplitude * cosTheta;
        const float decay = exp(wave.wavenumber * fmin(0.0f, r.y - body->water.x));
        const float horizontal = wave.q * wave.amplitude * wave.omega * cosTheta * decay;
        const float3 uw = (float3)(horizontal * d.x, wave.amplitude * wave.omega * sinTheta * decay,
                                   horizontal * d.y);
        u += uw;
        if (below) dudy += wave.wavenumber * uw;
    }
    *height = y;
    *velocity = u;
    *velocityDy = dudy;
}

/// Surface height above (r.x, r.z), relative to the body's centre of mass. `waterModel` is a
/// literal at every call, so each kernel variant keeps only its own branch.
PL_INLINE float surfaceHeight(const int waterModel, const PlBody* body,
                              __global const PlWave* waves, __global const float* grid,
                              int gridCountX, int gridCountZ, float3 r) {
    const float level = body->water.x;
    if (waterModel == PL_WATER_GERSTNER) {  // the velocity, unused, is compiled away
        float y;
        float3 unusedVelocity, unusedDy;
        gerstnerSample(body, waves, r, &y, &unusedVelocity, &unusedDy);
        return y;
    }
    if (waterModel == PL_WATER_HEIGHTFIELD) {
        // Cell coordinates as an integer cell of c plus a small float offset: exact far away.
        const float gx = body->grid.x + r.x * body->grid.z;
        const float gz = body->grid.y + r.z * body->grid.z;
        const float cx = floor(gx), cz = floor(gz);
        const float fx = gx - cx, fz = gz - cz;
        const int i0 = clamp(body->gridCellX + (int)cx, 0, gridCountX - 1);
        const int i1 = clamp(body->gridCellX + (int)cx + 1, 0, gridCountX - 1);
        const int j0 = clamp(body->gridCellZ + (int)cz, 0, gridCountZ - 1);
        const int j1 = clamp(body->gridCellZ + (int)cz + 1, 0, gridCountZ - 1);
        const float h = (1.0f - fz) * ((1.0f - fx) * grid[j0 * gridCountX + i0] +
                                       fx * grid[j0 * gridCountX + i1]) +
                        fz * ((1.0f - fx) * grid[j1 * gridCountX + i0] +
                              fx * grid[j1 * gridCountX + i1]);
        return level + h;
    }
    return level;
}

/// Adds a vector to three consecutive slots of a work-item's sums.
PL_INLINE void addVector(float* sum, int slot, float3 v) {
    sum[slot + 0] += v.x;
    sum[slot + 1] += v.y;
    sum[slot + 2] += v.z;
}

/// Share of an entry's surface under water, for drag and wetted area: the entry spans about
/// sqrt(area) times the horizontal part of its normal in height, and is wet in proportion to
/// how far the surface reaches up it. Continuous in the depth (a hard step would make drag
/// jump as a ring of texels crosses the surface); hydrostatics need no such share, their
/// integrands vanish at the surface.
PL_INLINE float wetShare(float depth, float3 areaVector, float area) {
    const float length2 = dot(areaVector, areaVector);
    const float upright = length2 > 0.0f ? areaVector.y * areaVector.y / length2 : 1.0f;
    const float extent = sqrt(area * fmax(0.0f, 1.0f - upright));
    if (extent <= 0.0f) return depth > 0.0f ? 1.0f : 0.0f;
    return clamp(0.5f + depth / extent, 0.0f, 1.0f);
}

/// Work-items that take part in summing the slots: PL_SLOT_PARTS of them per slot. Work-item j
/// sums slot j % PL_SUM_SLOTS of every PL_SLOT_PARTS-th row from row j / PL_SUM_SLOTS, so the
/// first stage runs on PL_SLOT_PARTS x PL_SUM_SLOTS work-items at once, reading consecutive
/// addresses, and the second adds PL_SLOT_PARTS values per slot: two local barriers where a
/// tree over the work-items takes log2(PL_WORKGROUP_SIZE) + 1.
#define PL_SLOT_PARTS (PL_WORKGROUP_SIZE / PL_SUM_SLOTS)
#define PL_SLOT_WORKERS (PL_SLOT_PARTS * PL_SUM_SLOTS)

/// Adds each summing work-item's `part` (its share of slot lid % PL_SUM_SLOTS) into
/// out[0 .. PL_SUM_SLOTS), through scratch[0 .. PL_SLOT_WORKERS). Called by every work-item of
/// the group, after a barrier that ends every read of scratch.
PL_INLINE void addSlotParts(__local acc_t* scratch, uint lid, acc_t part, __global acc_t* out) {
    if (lid < PL_SLOT_WORKERS) scratch[lid] = part;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid < PL_SUM_SLOTS) {
        acc_t total = 0;
        for (uint q = 0; q < PL_SLOT_PARTS; ++q) total += scratch[q * PL_SUM_SLOTS + lid];
        out[lid] = total;
    }
}

/// Reduction of the group's rows of sums (scratch[row * PL_SUM_SLOTS + slot], one row per
/// work-item, already stored) into out[0 .. PL_SUM_SLOTS). Where `onlyFirst` (uniform over the
/// group) only work-item 0's row holds anything (it must be stored; the others need not be),
/// and only that row is read; the barriers are not skipped, so that every work-item runs the
/// same barriers whatever the tile (PoCL 3.1 wrote past the partials where a group left by a
/// uniform branch after a barrier).
PL_INLINE void reduceGroup(__local acc_t* scratch, uint lid, __global acc_t* out, bool onlyFirst) {
    barrier(CLK_LOCAL_MEM_FENCE);
    acc_t part = 0;
    if (lid < PL_SLOT_WORKERS) {
        const uint slot = lid % PL_SUM_SLOTS;
        const uint rows = onlyFirst ? 1 : PL_WORKGROUP_SIZE;
        for (uint row = lid / PL_SUM_SLOTS; row < rows; row += PL_SLOT_PARTS)
            part += scratch[row * PL_SUM_SLOTS + slot];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    addSlotParts(scratch, lid, part, out);
}

/// Slots of the symmetric index pairs and triples in PlTileMoments (plimsoll_shared.h).
__constant int PL_PAIR[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
__constant int PL_TRIPLE[3][3][3] = {{{0, 1, 2}, {1, 3, 4}, {2, 4, 5}},
                                     {{1, 3, 4}, {3, 6, 7}, {4, 7, 8}},
                                     {{2, 4, 5}, {4, 7, 8}, {5, 8, 9}}};
__constant int PL_PAIR_FIRST[6] = {0, 0, 0, 1, 1, 2};
__constant int PL_PAIR_SECOND[6] = {0, 1, 2, 1, 2, 2};

PL_INLINE float secondMoment(__global const PlTileMoments* m, int i, int j, int k) {
    return m->second[6 * i + PL_PAIR[j][k]];
}
PL_INLINE float thirdMoment(__global const PlTileMoments* m, int i, int j, int k, int l) {
    return m->third[10 * i + PL_TRIPLE[j][k][l]];
}

/// The water over one tile, about the tile's centre rt (world axes, relative to c): the
/// quadratic f + g.x + x^T H x / 2 through the 3 x 3 heights at spacing rho (the tile's radius)
/// about rt.xz, and how far that quadratic misses the true surface at 16 points between them;
/// on Gerstner waves the water's velocity at rt and its gradient (central differences at
/// +-rho/2 across, the decay's derivative along y), so that over the tile u(r) = u + J (r - rt).
typedef struct {
    float f, gx, gz, hxx, hxz, hzz;
    float misfit;
    float3 u;
    float3 J[3];  /* rows: J[i] = grad u_i */
} PlTileWater;

/// The tile's quadratic at the horizontal offset (dx, dz) from its centre.
PL_INLINE float tileQuadraticAt(const PlTileWater* w, float dx, float dz) {
    return w->f + w->gx * dx + w->gz * dz + 0.5f * (w->hxx * dx * dx + 2.0f * w->hxz * dx * dz + w->hzz * dz * dz);
}

/// Still flat water at `level` over a tile: exact.
PL_INLINE PlTileWater flatTileWater(float level) {
    PlTileWater w;
    w.f = level;
    w.gx = w.gz = w.hxx = w.hxz = w.hzz = w.misfit = 0.0f;
    w.u = (float3)(0.0f, 0.0f, 0.0f);
    for (int i = 0; i < 3; ++i) w.J[i] = (float3)(0.0f, 0.0f, 0.0f);
    return w;
}

/// Work-items 0..24 sample the surface on a 5 x 5 grid at spacing rho/2 about rt.xz, on Gerstner
/// waves the water's velocity at the same points at the height of rt too (from the same solve;
/// its y derivative at the centre in closed form): one round of the group, in parallel. After
/// the barrier every work-item forms the same quadratic and velocity gradient from the samples.
PL_INLINE PlTileWater sampleTileWater(const int waterModel, const PlBody* body,
                                      __global const PlWave* waves, __global const float* grid,
                                      int gridCountX, int gridCountZ, float3 rt, float rho,
                                      uint lid, __local float* heights, __local float4* velocities) {
    const float halfStep = 0.5f * rho;
    if (lid < 25) {
        const float3 r = rt + (float3)(((int)(lid % 5) - 2) * halfStep, 0.0f, ((int)(lid / 5) - 2) * halfStep);
        if (waterModel == PL_WATER_GERSTNER) {
            float height;
            float3 u, dudy;
            gerstnerSample(body, waves, r, &height, &u, &dudy);
            heights[lid] = height;
            velocities[lid] = (float4)(u, 0.0f);
            if (lid == 12) velocities[25] = (float4)(dudy, 0.0f);
        } else {
            heights[lid] = surfaceHeight(waterModel, body, waves, grid, gridCountX, gridCountZ, r);
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    PlTileWater w = flatTileWater(0.0f);  // still water unless Gerstner (below)
#define PL_H(i, j) heights[(2 + (j)) * 5 + 2 + (i)]
    const float inverse = 1.0f / rho, inverse2 = inverse * inverse;
    w.f = PL_H(0, 0);
    w.gx = (PL_H(2, 0) - PL_H(-2, 0)) * 0.5f * inverse;
    w.gz = (PL_H(0, 2) - PL_H(0, -2)) * 0.5f * inverse;
    w.hxx = (PL_H(2, 0) - 2.0f * w.f + PL_H(-2, 0)) * inverse2;
    w.hzz = (PL_H(0, 2) - 2.0f * w.f + PL_H(0, -2)) * inverse2;
    w.hxz = (PL_H(2, 2) - PL_H(2, -2) - PL_H(-2, 2) + PL_H(-2, -2)) * 0.25f * inverse2;
    float misfit = 0.0f;
    for (int j = -2; j <= 2; ++j)
        for (int i = -2; i <= 2; ++i) {
            misfit = fmax(misfit, fabs(PL_H(i, j) - tileQuadraticAt(&w, i * halfStep, j * halfStep)));
        }
#undef PL_H
    w.misfit = misfit;
    if (waterModel == PL_WATER_GERSTNER) {
        // The samples at +-rho/2 along x (11, 13) and z (7, 17) about the centre (12).
        w.u = velocities[12].xyz;
        const float3 dx = (velocities[13].xyz - velocities[11].xyz) * inverse;
        const float3 dy = velocities[25].xyz;
        const float3 dz = (velocities[17].xyz - velocities[7].xyz) * inverse;
        w.J[0] = (float3)(dx.x, dy.x, dz.x);
        w.J[1] = (float3)(dx.y, dy.y, dz.y);
        w.J[2] = (float3)(dx.z, dy.z, dz.z);
    }
    return w;
}

/// R (object -> world) as a matrix, from its rows in body->rotation.
PL_INLINE void rotationOf(const PlBody* body, float R[3][3]) {
    for (int i = 0; i < 3; ++i) {
        R[i][0] = body->rotation[i].x;
        R[i][1] = body->rotation[i].y;
        R[i][2] = body->rotation[i].z;
    }
}

/// R^T v (world -> object) with R's rows in body->rotation.
PL_INLINE float3 rotateToObject(const PlBody* body, float3 v) {
    return v.x * body->rotation[0].xyz + v.y * body->rotation[1].xyz + v.z * body->rotation[2].xyz;
}

/// Adds to `sum` what the per-entry loop sums over a tile whose entries all lie under the
/// water, fully wet, from the tile's moments: with the depth in object axes about the tile's
/// centre, d(s) = alpha + beta.s + s^T K s / 2 (alpha = f - rt.y, beta = R^T (gx, -1, gz),
/// K = R^T H R), the depth integrals
///   D0 = sum a d,  D1 = sum a s^T d,  E = sum a d^2 (less sum a (s^T K s)^2 / 4, fourth order),
/// turned to world axes (W0 = R D0, W1 = R D1 R^T, WE = R E), give
///   V = -W0_y,  moments -(rt_x W0_y + W1_yx), -(rt_y W0_y + W1_yy + WE_y / 2), -(rt_z W0_y + W1_yz),
///   F = -rho g W0,  T = -rho g (rt x W0 + R xi),  xi_i = eps_ijk D1_kj = (sum d s x a)_i.
/// Under flat water (g = H = 0) they are exact: the same numbers the loop sums, up to rounding.
PL_INLINE void submergedTileFromMoments(const PlBody* body, __global const PlTileMoments* m,
                                        float3 rt, const PlTileWater* w, const bool curved,
                                        float* sum) {
    float R[3][3];
    rotationOf(body, R);
    const float alpha = w->f - rt.y;
    const float3 beta3 = rotateToObject(body, (float3)(w->gx, -1.0f, w->gz));
    const float beta[3] = {beta3.x, beta3.y, beta3.z};
    // K = R^T H R, H's y row and column zero; packed as pair slots, off-diagonals doubled.
    float Ks[6];
    for (int slot = 0; slot < 6; ++slot) {
        const int a = PL_PAIR_FIRST[slot], b = PL_PAIR_SECOND[slot];
        const float k = R[0][a] * w->hxx * R[0][b] + R[0][a] * w->hxz * R[2][b] +
                        R[2][a] * w->hxz * R[0][b] + R[2][a] * w->hzz * R[2][b];
        Ks[slot] = a == b ? k : 2.0f * k;
    }
    const float N0[3] = {m->sum.x, m->sum.y, m->sum.z};
    float D0[3], D1[3][3], E[3];
    for (int i = 0; i < 3; ++i) {
        const float N1[3] = {m->first[i].x, m->first[i].y, m->first[i].z};
        float n1b = 0.0f, n2K = 0.0f, n2bb = 0.0f, bn3K = 0.0f;
        float n2b[3], n3K[3];
        for (int j = 0; j < 3; ++j) {
            n1b += N1[j] * beta[j];
            n2b[j] = secondMoment(m, i, j, 0) * beta[0] + secondMoment(m, i, j, 1) * beta[1] +
                     secondMoment(m, i, j, 2) * beta[2];
            n2bb += n2b[j] * beta[j];
            float c = 0.0f;
            if (curved)  // a literal at the call: flat water skips the third moments
                for (int slot = 0; slot < 6; ++slot)
                    c += thirdMoment(m, i, j, PL_PAIR_FIRST[slot], PL_PAIR_SECOND[slot]) * Ks[slot];
            n3K[j] = c;
            bn3K += beta[j] * c;
        }
        if (curved)
            for (int slot = 0; slot < 6; ++slot) n2K += m->second[6 * i + slot] * Ks[slot];
        D0[i] = alpha * N0[i] + n1b + 0.5f * n2K;
        for (int j = 0; j < 3; ++j) D1[i][j] = alpha * N1[j] + n2b[j] + 0.5f * n3K[j];
        E[i] = alpha * alpha * N0[i] + 2.0f * alpha * n1b + n2bb + alpha * n2K + bn3K;
    }
    // World axes: W0 = R D0; of W1 = R D1 R^T only its y row, and its antisymmetric part through
    // the axial vector, eps_ijk W1_kj = (R xi)_i with xi_i = eps_ijk D1_kj (sum d s x a).
    const float3 yRow = body->rotation[1].xyz;
    const float3 W0 = rotateToWorld(body, (float3)(D0[0], D0[1], D0[2]));
    const float3 RD1y = yRow.x * (float3)(D1[0][0], D1[0][1], D1[0][2]) +
                        yRow.y * (float3)(D1[1][0], D1[1][1], D1[1][2]) +
                        yRow.z * (float3)(D1[2][0], D1[2][1], D1[2][2]);
    const float3 W1y = rotateToWorld(body, RD1y);
    const float3 xi = (float3)(D1[2][1] - D1[1][2], D1[0][2] - D1[2][0], D1[1][0] - D1[0][1]);
    const float WEy = dot(yRow, (float3)(E[0], E[1], E[2]));
    const float rhoG = body->fluid.x;
    sum[PL_SUM_VOLUME] -= W0.y;
    sum[PL_SUM_MOMENT + 0] -= rt.x * W0.y + W1y.x;
    sum[PL_SUM_MOMENT + 1] -= rt.y * W0.y + W1y.y + 0.5f * WEy;
    sum[PL_SUM_MOMENT + 2] -= rt.z * W0.y + W1y.z;
    addVector(sum, PL_SUM_PRESSURE_F, -rhoG * W0);
    addVector(sum, PL_SUM_PRESSURE_T, -rhoG * (cross(rt, W0) + rotateToWorld(body, xi)));
    sum[PL_SUM_WETTED_AREA] += m->sum.w;
    sum[PL_SUM_COUNT] += m->first[0].w;
    sum[PL_SUM_TILES_CLOSED] += 1.0f;
}

/// The pressure drag of a wholly wet tile whose entries all keep one sign of A.v, added to
/// `sum` from its moments (no skin friction: its |v_t| is not a polynomial). With the
/// relative velocity linear over the tile, v = vt + L (r - rt) (L = [spin]x - J, J the water
/// velocity's gradient), in object axes v(s) = u + B s (u = R^T vt, B = R^T L R), each facing
/// entry adds -k (a.v) v (k = rho C_d / 2):
///   F = -k R [(N0.u) u + B P + (B:N1) u + B X],  P = N1^T u,  X_m = sum_ij B_ij N2_i,jm,
///   T = rt x F + R t,  t_i = -k eps_ijl Y_jl,  Y_jl = u_l (P_j + X_j) + sum_m B_lm (Q_jm + Z_jm),
///   Q_jm = sum_i u_i N2_i,jm,  Z_jm = sum_ip B_ip N3_i,pjm.
/// Returns false, adding nothing, where the sign of a.v may change over the tile: the cone of
/// its normals (axis e, cosine ca) against u, widened by |B|_F times its radius. Adds nothing
/// either unless `accumulate` (the group's other work-items only take the decision).
PL_INLINE bool facingDragFromMoments(const PlBody* body, const PlTile* tile,
                                     __global const PlTileMoments* m, float3 rt,
                                     const PlTileWater* w, bool accumulate, float* sum) {
    const float ca = tile->cone.w;
    if (ca <= 0.0f) return false;
    const float3 spin = body->spin.xyz;
    const float3 vt = body->velocity.xyz + cross(spin, rt) - w->u;
    // L = [spin]x - J, by rows; then B = R^T L R.
    const float3 L[3] = {(float3)(0.0f, -spin.z, spin.y) - w->J[0],
                         (float3)(spin.z, 0.0f, -spin.x) - w->J[1],
                         (float3)(-spin.y, spin.x, 0.0f) - w->J[2]};
    float R[3][3];
    rotationOf(body, R);
    float LR[3][3], B[3][3];
    for (int i = 0; i < 3; ++i) {
        const float Li[3] = {L[i].x, L[i].y, L[i].z};
        for (int j = 0; j < 3; ++j) LR[i][j] = Li[0] * R[0][j] + Li[1] * R[1][j] + Li[2] * R[2][j];
    }
    float bNorm2 = 0.0f;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            B[i][j] = R[0][i] * LR[0][j] + R[1][i] * LR[1][j] + R[2][i] * LR[2][j];
            bNorm2 += B[i][j] * B[i][j];
        }
    const float3 u3 = rotateToObject(body, vt);
    const float speed = length(u3);
    if (!(speed > 0.0f)) return false;
    const float spread = sqrt(bNorm2) * tile->sphere.w;
    const float cosTheta = dot(tile->cone.xyz, u3) / speed;
    const float sinTheta = sqrt(fmax(0.0f, 1.0f - cosTheta * cosTheta));
    const float sa = sqrt(fmax(0.0f, 1.0f - ca * ca));
    const bool facing = speed * (cosTheta * ca - sinTheta * sa) > spread;
    const bool trailing = speed * (cosTheta * ca + sinTheta * sa) < -spread;
    if (!facing && !trailing) return false;
    if (!accumulate) return true;
    sum[PL_SUM_TILES_DRAG_CLOSED] += 1.0f;
    if (trailing) return true;  // no entry faces the flow: no pressure drag
    const float u[3] = {u3.x, u3.y, u3.z};
    const float N0[3] = {m->sum.x, m->sum.y, m->sum.z};
    float N1[3][3];
    for (int i = 0; i < 3; ++i) {
        N1[i][0] = m->first[i].x;
        N1[i][1] = m->first[i].y;
        N1[i][2] = m->first[i].z;
    }
    float P[3], X[3], BN1 = 0.0f;
    for (int j = 0; j < 3; ++j) {
        P[j] = u[0] * N1[0][j] + u[1] * N1[1][j] + u[2] * N1[2][j];
        float x = 0.0f;
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) x += B[i][k] * secondMoment(m, i, k, j);
        X[j] = x;
        for (int i = 0; i < 3; ++i) BN1 += B[i][j] * N1[i][j];
    }
    const float N0u = N0[0] * u[0] + N0[1] * u[1] + N0[2] * u[2];
    const float k = body->fluid.y;
    float Fo[3];
    for (int i = 0; i < 3; ++i) {
        Fo[i] = -k * (N0u * u[i] + B[i][0] * (P[0] + X[0]) + B[i][1] * (P[1] + X[1]) +
                      B[i][2] * (P[2] + X[2]) + BN1 * u[i]);
    }
    // Y_jl = u_l (P_j + X_j) + sum_m B_lm (Q_jm + Z_jm), QZ symmetric in (j, m).
    float QZ[6];
    for (int slot = 0; slot < 6; ++slot) {
        const int j = PL_PAIR_FIRST[slot], mm = PL_PAIR_SECOND[slot];
        float q = 0.0f;
        for (int i = 0; i < 3; ++i) {
            q += u[i] * secondMoment(m, i, j, mm);
            for (int p = 0; p < 3; ++p) q += B[i][p] * thirdMoment(m, i, p, j, mm);
        }
        QZ[slot] = q;
    }
    float Y[3][3];
    for (int j = 0; j < 3; ++j)
        for (int l = 0; l < 3; ++l)
            Y[j][l] = u[l] * (P[j] + X[j]) + B[l][0] * QZ[PL_PAIR[j][0]] +
                      B[l][1] * QZ[PL_PAIR[j][1]] + B[l][2] * QZ[PL_PAIR[j][2]];
    float to[3];
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, l = (i + 2) % 3;
        to[i] = -k * (Y[j][l] - Y[l][j]);
    }
    const float3 F = rotateToWorld(body, (float3)(Fo[0], Fo[1], Fo[2]));
    const float3 T = cross(rt, F) + rotateToWorld(body, (float3)(to[0], to[1], to[2]));
    addVector(sum, PL_SUM_DRAG_F, F);
    addVector(sum, PL_SUM_DRAG_T, T);
    return true;
}

/// The water over an entry at r from its tile's water `w` (sampled about rt): the quadratic's
/// height and the velocity linear over the tile. The velocity's y derivative holds below the
/// mean level `level` only (the orbital motion is not continued above it), so the offset along
/// y is taken between the two points' heights clamped to the level.
PL_INLINE float tileWaterAt(const PlTileWater* w, float3 rt, float level, float3 r, float3* velocity) {
    const float dx = r.x - rt.x, dz = r.z - rt.z;
    const float dy = fmin(r.y, level) - fmin(rt.y, level);
    const float3 d = (float3)(dx, dy, dz);
    *velocity = w->u + (float3)(dot(w->J[0], d), dot(w->J[1], d), dot(w->J[2], d));
    return tileQuadraticAt(w, dx, dz);
}

/// Adds a work-item's share of a tile's entries to `sum`: the hydrostatics and wetted area
/// where `hydroSums`, the drag where `dragSums`. Where `fromTileWater` (Gerstner waves whose
/// quadratic holds over the tile) the entries take the tile's water (tileWaterAt) rather than a
/// Gerstner solve each: at the waterline, as the fast CPU path does, a work-item's chain of
/// entries is then arithmetic alone; elsewhere each entry solves for its undisplaced point.
PL_INLINE void entrySums(__global const float4* positions, __global const float4* areaVectors,
                         const PlTile* tile, const PlBody* body, __global const PlWave* waves,
                         __global const float* grid, int gridCountX, int gridCountZ, uint lid,
                         const int waterModel, const bool hydroSums, const bool dragSums,
                         const PlTileWater* w, float3 rt, const bool fromTileWater, float* sum) {
    const float rhoG = body->fluid.x;
    const float halfRhoCd = body->fluid.y;
    const float halfRhoCf = body->fluid.z;
    // A fixed trip count (PL_ITEMS_PER_THREAD, set at build time) that the compiler unrolls.
    for (int k = 0; k < PL_ITEMS_PER_THREAD; ++k) {
        const uint i = tile->begin + k * PL_WORKGROUP_SIZE + lid;
        if (i >= tile->end) break;
        const float4 p = positions[i];
        const float3 r = rotateToWorld(body, p.xyz);
        // On Gerstner waves with drag the height and the water's velocity share one solve.
        float f;
        float3 waterVelocity = (float3)(0.0f, 0.0f, 0.0f), unused;
        if (waterModel == PL_WATER_GERSTNER && fromTileWater)
            f = tileWaterAt(w, rt, body->water.x, r, &waterVelocity);
        else if (waterModel == PL_WATER_GERSTNER && dragSums)
            gerstnerSample(body, waves, r, &f, &waterVelocity, &unused);
        else
            f = surfaceHeight(waterModel, body, waves, grid, gridCountX, gridCountZ, r);
        const float depth = f - r.y;
        const float3 a = rotateToWorld(body, areaVectors[i].xyz);
        const float wet = wetShare(depth, a, p.w);
        if (wet <= 0.0f) continue;
        if (hydroSums) {
            if (depth > 0.0f) {
                // Hydrostatics with fields that vanish on the surface (exact for any height field).
                sum[PL_SUM_VOLUME] -= a.y * depth;
                sum[PL_SUM_MOMENT + 0] -= a.y * r.x * depth;
                sum[PL_SUM_MOMENT + 1] += a.y * 0.5f * (r.y * r.y - f * f);
                sum[PL_SUM_MOMENT + 2] -= a.y * r.z * depth;
                const float3 pressureForce = -(rhoG * depth) * a;
                addVector(sum, PL_SUM_PRESSURE_F, pressureForce);
                addVector(sum, PL_SUM_PRESSURE_T, cross(r, pressureForce));
                sum[PL_SUM_COUNT] += 1.0f;
            }
            sum[PL_SUM_WETTED_AREA] += wet * p.w;
        }
        if (!dragSums) continue;
        // Drag: pressure drag on the side facing the relative flow, optional skin friction.
        const float3 v = body->velocity.xyz + cross(body->spin.xyz, r) - waterVelocity;
        const float speed = length(v);
        float3 drag = (float3)(0.0f, 0.0f, 0.0f);
        if (speed > 0.0f) {
            const float facing = dot(a, v) / speed;
            if (facing > 0.0f) drag -= (wet * halfRhoCd * facing * speed) * v;
            if (halfRhoCf > 0.0f && p.w > 0.0f) {
                const float3 n = a / fmax(length(a), 1e-30f);
                const float3 tangential = v - dot(v, n) * n;
                drag -= (wet * halfRhoCf * p.w * length(tangential)) * tangential;
            }
        }
        addVector(sum, PL_SUM_DRAG_F, drag);
        addVector(sum, PL_SUM_DRAG_T, cross(r, drag));
    }
}

/// The body of every buoyancy_tiles_* kernel. waterModel and withDrag are literal constants at
/// each call: the compiler drops the branches of the other water models (half the time on
/// PoCL) and, for bodies at rest in still water, the drag.
///
/// Each tile is first placed against the water, uniformly across its group: dry (nothing to
/// add), wholly wet (its hydrostatics, and its drag where a.v keeps one sign, from its moments:
/// submergedTileFromMoments, facingDragFromMoments) or at the waterline (entry by entry). On
/// flat water the plane is exact; on waves the water over the tile is the quadratic of
/// sampleTileWater, and a tile takes it only where that quadratic misses the surface by at most
/// body.water.z at its check points (0: never; every wet tile on waves goes entry by entry).
PL_INLINE void buoyancyTiles(__global const float4* positions, __global const float4* areaVectors,
                          __global const PlTile* tiles, __global const PlTileMoments* moments,
                          __global const PlBody* bodies,
                          __global const PlWave* waves, __global const float* grid,
                          int gridCountX, int gridCountZ, __global acc_t* partials,
                          __local acc_t* scratch, __local float* heights,
                          __local float4* velocities, const int waterModel, const int withDrag) {
    const uint tileIndex = get_group_id(0);
    const uint lid = get_local_id(0);
    const PlTile tile = tiles[tileIndex];
    const PlBody body = bodies[tile.body];
    __global acc_t* partial = partials + tileIndex * PL_SUM_SLOTS;

    // Uniform per group: either every work-item returns here or none does.
    const float3 rt = rotateToWorld(&body, tile.sphere.xyz);
    const float rho = tile.sphere.w;
    if (rt.y - rho > body.water.y) {
        if (lid < PL_SUM_SLOTS) partial[lid] = lid == PL_SUM_TILES_DRY ? 1 : 0;
        return;
    }
    // Wholly under still flat water: the tile's moments give every sum. The group leaves here,
    // before any barrier, as the kernel did before waves had the scheme; the same return
    // further down (after the tile was placed, with the tile's sums in `sum`) corrupted PoCL
    // 3.1's heap, so only this case has it (sphere at rest at 1024^2 on PoCL, 474 tiles in
    // closed form: 0.77 ms a call with it, 0.93-1.31 ms with them all through the reduction).
    if (waterModel == PL_WATER_FLAT && !withDrag && rt.y + rho < body.water.x) {
        if (lid == 0) {
            float tileSum[PL_SUM_SLOTS];
            for (int s = 0; s < PL_SUM_SLOTS; ++s) tileSum[s] = 0.0f;
            const PlTileWater flat = flatTileWater(body.water.x);
            submergedTileFromMoments(&body, &moments[tileIndex], rt, &flat, false, tileSum);
            for (int s = 0; s < PL_SUM_SLOTS; ++s) partial[s] = tileSum[s];
        }
        return;
    }
    PlTileWater w = flatTileWater(body.water.x);
    bool quadraticHolds = true;
    if (waterModel != PL_WATER_FLAT) {
        w = sampleTileWater(waterModel, &body, waves, grid, gridCountX, gridCountZ, rt, rho, lid,
                            heights, velocities);
        quadraticHolds = body.water.z > 0.0f && w.misfit <= body.water.z;
    }
    // The quadratic's departure from f over the tile's disc, and the tile's vertical reach.
    const float departure = sqrt(w.gx * w.gx + w.gz * w.gz) * rho +
                            0.5f * sqrt(w.hxx * w.hxx + w.hzz * w.hzz + 2.0f * w.hxz * w.hxz) * rho * rho +
                            w.misfit;
    const bool dry = quadraticHolds && rt.y - rho > w.f + departure;
    const bool submerged = quadraticHolds && rt.y + rho < w.f - departure;

    float sum[PL_SUM_SLOTS];
    for (int s = 0; s < PL_SUM_SLOTS; ++s) sum[s] = 0.0f;
    bool hydroPerEntry = !dry, dragPerEntry = withDrag && !dry;
    if (dry && lid == 0) sum[PL_SUM_TILES_DRY] = 1.0f;
    if (submerged) {
        hydroPerEntry = false;
        if (lid == 0) submergedTileFromMoments(&body, &moments[tileIndex], rt, &w,
                                                     waterModel != PL_WATER_FLAT, sum);
        // Every work-item decides alike; work-item 0 alone adds the sums.
        if (withDrag && !(body.fluid.z > 0.0f))  // skin friction goes entry by entry
            dragPerEntry = !facingDragFromMoments(&body, &tile, &moments[tileIndex], rt, &w,
                                                  lid == 0, sum);
    }
    if (hydroPerEntry || dragPerEntry)
        entrySums(positions, areaVectors, &tile, &body, waves, grid, gridCountX, gridCountZ,
                  lid, waterModel, hydroPerEntry, dragPerEntry, &w, rt,
                  waterModel == PL_WATER_GERSTNER && quadraticHolds, sum);
    // Every case after the water's barrier ends in the one reduction, work-item 0 holding the
    // closed forms' sums (alone, where no entry was visited): PoCL 3.1 wrote past the partials
    // where the group left by a branch after that barrier (a return, or the reduction on one
    // side only), uniform as it was.
    const bool entries = hydroPerEntry || dragPerEntry;
    if (entries || lid == 0)
        for (int s = 0; s < PL_SUM_SLOTS; ++s) scratch[lid * PL_SUM_SLOTS + s] = sum[s];
    reduceGroup(scratch, lid, partial, !entries);
}

#define PL_TILES_KERNEL(name, model, drag)                                                   \
    __kernel __attribute__((reqd_work_group_size(PL_WORKGROUP_SIZE, 1, 1))) void name(           \
        __global const float4* positions, __global const float4* areaVectors,                    \
        __global const PlTile* tiles, __global const PlTileMoments* moments,                     \
        __global const PlBody* bodies,                                                           \
        __global const PlWave* waves, __global const float* grid, int gridCountX,                \
        int gridCountZ, __global acc_t* partials) {                                              \
        __local acc_t scratch[PL_SUM_SLOTS * PL_WORKGROUP_SIZE];                                 \
        __local float heights[25];                                                               \
        __local float4 velocities[26];                                                            \
        buoyancyTiles(positions, areaVectors, tiles, moments, bodies, waves, grid, gridCountX,  \
                      gridCountZ, partials, scratch, heights, velocities, model, drag);         \
    }

PL_TILES_KERNEL(buoyancy_tiles_flat, PL_WATER_FLAT, 1)
PL_TILES_KERNEL(buoyancy_tiles_flat_still, PL_WATER_FLAT, 0)
PL_TILES_KERNEL(buoyancy_tiles_gerstner, PL_WATER_GERSTNER, 1)
PL_TILES_KERNEL(buoyancy_tiles_gerstner_still, PL_WATER_GERSTNER, 0)
PL_TILES_KERNEL(buoyancy_tiles_heightfield, PL_WATER_HEIGHTFIELD, 1)
PL_TILES_KERNEL(buoyancy_tiles_heightfield_still, PL_WATER_HEIGHTFIELD, 0)

/// One work-group per chunk: a range [chunk.x, chunk.y) of one body's tiles, whose partials
/// lie one after another (tile-major, PL_SUM_SLOTS each). The summing work-items walk them in
/// strides of PL_SLOT_WORKERS, a multiple of PL_SUM_SLOTS: each stays on its slot and together
/// they read consecutive addresses. The host adds a body's chunks.
__kernel __attribute__((reqd_work_group_size(PL_WORKGROUP_SIZE, 1, 1)))
void reduce_chunks(__global const acc_t* partials, __global const uint2* chunks,
                   __global acc_t* totals) {
    __local acc_t scratch[PL_SLOT_WORKERS];
    const uint chunkIndex = get_group_id(0);
    const uint lid = get_local_id(0);
    const uint2 chunk = chunks[chunkIndex];
    acc_t part = 0;
    if (lid < PL_SLOT_WORKERS) {
        const uint end = chunk.y * PL_SUM_SLOTS;
        for (uint i = chunk.x * PL_SUM_SLOTS + lid; i < end; i += PL_SLOT_WORKERS)
            part += partials[i];
    }
    addSlotParts(scratch, lid, part, totals + chunkIndex * PL_SUM_SLOTS);
}

/// Plain copy, for measuring the device's memory bandwidth (plimsoll bench).
__kernel void copy_float4(__global const float4* source, __global float4* target) {
    const size_t i = get_global_id(0);
    target[i] = source[i];
}
