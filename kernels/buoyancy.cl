// Per-frame buoyancy of a batch of bodies over their compacted texel entries.
// plimsoll_shared.h is prepended at build time; PL_ACC_DOUBLE is defined when the device has
// cl_khr_fp64. The C++ reference is engine/src/physics/buoyancy_reference.cpp (same formulas, double
// precision, no culling); tests hold this file against it.
//
// Launch 1, buoyancy_tiles_<water model>[_still]: one work-group per tile of up to
// PL_WORKGROUP_SIZE x PL_ITEMS_PER_THREAD entries ("_still": no drag, for bodies at rest in
// still water). A tile whose
// bounding sphere lies entirely above the highest possible water surface adds nothing and reads
// no texel (a floating body skips most of its dry half). Each work-item accumulates its entries
// in acc_t, then the group reduces all slots at once in local memory and writes one partial.
// Launch 2, reduce_bodies: one work-group per body sums that body's tile partials.

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

/// Surface height above (r.x, r.z), relative to the body's centre of mass. `waterModel` is a
/// literal at every call, so each kernel variant keeps only its own branch.
PL_INLINE float surfaceHeight(const int waterModel, const PlBody* body,
                              __global const PlWave* waves, __global const float* grid,
                              int gridCountX, int gridCountZ, float3 r) {
    const float level = body->water.x;
    if (waterModel == PL_WATER_GERSTNER) {
        const float2 x0 = gerstnerUndisplaced(body, waves, r.xz);
        float y = level;
        for (int w = 0; w < body->waveCount; ++w) {
            const PlWave wave = waves[body->waveBegin + w];
            const float2 d = (float2)(wave.directionX, wave.directionZ);
            y += wave.amplitude * cos(wave.wavenumber * dot(d, x0) + wave.phase);
        }
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

/// Orbital velocity of the water at r (Gerstner only), decaying below the mean level.
PL_INLINE float3 waterVelocity(const int waterModel, const PlBody* body,
                               __global const PlWave* waves, float3 r) {
    float3 u = (float3)(0.0f, 0.0f, 0.0f);
    if (waterModel != PL_WATER_GERSTNER) return u;
    const float2 x0 = gerstnerUndisplaced(body, waves, r.xz);
    for (int w = 0; w < body->waveCount; ++w) {
        const PlWave wave = waves[body->waveBegin + w];
        const float2 d = (float2)(wave.directionX, wave.directionZ);
        const float theta = wave.wavenumber * dot(d, x0) + wave.phase;
        const float decay = exp(wave.wavenumber * fmin(0.0f, r.y - body->water.x));
        const float horizontal = wave.q * wave.amplitude * wave.omega * cos(theta) * decay;
        u += (float3)(horizontal * d.x, wave.amplitude * wave.omega * sin(theta) * decay,
                      horizontal * d.y);
    }
    return u;
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

/// Tree reduction of the group's PL_SUM_SLOTS rows of `scratch` (one value per work-item
/// each, already stored) into out[0 .. PL_SUM_SLOTS).
PL_INLINE void reduceGroup(__local acc_t* scratch, uint lid, __global acc_t* out) {
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint stride = PL_WORKGROUP_SIZE / 2; stride > 0; stride >>= 1) {
        if (lid < stride) {
            for (int s = 0; s < PL_SUM_SLOTS; ++s)
                scratch[s * PL_WORKGROUP_SIZE + lid] += scratch[s * PL_WORKGROUP_SIZE + lid + stride];
        }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (lid < PL_SUM_SLOTS) out[lid] = scratch[lid * PL_WORKGROUP_SIZE];
}

/// The sums of a tile lying wholly under flat water at height f (relative to c), from its
/// moments: with r = R p and A = R a, Mw = sum A r^T = R M R^T and
/// Tw[i][j] = sum A_i r_j r_y = (R U R^T)[i][j], U[a][b] = sum_c T[a][b][c] R[y][c]. Then
///   V = Mw_yy - f Sw_y,  moments: Tw_yx - f Mw_yx, (Tw_yy - f^2 Sw_y)/2, Tw_yz - f Mw_yz,
///   F_i = -rho g (f Sw_i - Mw_iy),  T_i = -rho g eps_ijk (f Mw_kj - Tw_kj).
/// The same numbers the per-texel loop sums, up to rounding.
PL_INLINE void submergedTileFromMoments(const PlBody* body, __global const PlTileMoments* m,
                                        __global acc_t* out) {
    float R[3][3];
    for (int i = 0; i < 3; ++i) {
        R[i][0] = body->rotation[i].x;
        R[i][1] = body->rotation[i].y;
        R[i][2] = body->rotation[i].z;
    }
    float S[3] = {m->sum.x, m->sum.y, m->sum.z};
    float M[3][3], U[3][3];
    for (int a = 0; a < 3; ++a) {
        const float4 row = m->first[a];
        M[a][0] = row.x;
        M[a][1] = row.y;
        M[a][2] = row.z;
        for (int b = 0; b < 3; ++b) {
            const float4 t = m->second[3 * a + b];
            U[a][b] = t.x * R[1][0] + t.y * R[1][1] + t.z * R[1][2];
        }
    }
    float Sw[3], Mw[3][3], Tw[3][3];
    for (int i = 0; i < 3; ++i) {
        Sw[i] = R[i][0] * S[0] + R[i][1] * S[1] + R[i][2] * S[2];
        for (int j = 0; j < 3; ++j) {
            float mw = 0.0f, tw = 0.0f;
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) {
                    mw += R[i][a] * M[a][b] * R[j][b];
                    tw += R[i][a] * U[a][b] * R[j][b];
                }
            Mw[i][j] = mw;
            Tw[i][j] = tw;
        }
    }
    const float f = body->water.x;
    const float rhoG = body->fluid.x;
    out[PL_SUM_VOLUME] = Mw[1][1] - f * Sw[1];
    out[PL_SUM_MOMENT + 0] = Tw[1][0] - f * Mw[1][0];
    out[PL_SUM_MOMENT + 1] = 0.5f * (Tw[1][1] - f * f * Sw[1]);
    out[PL_SUM_MOMENT + 2] = Tw[1][2] - f * Mw[1][2];
    for (int i = 0; i < 3; ++i) {
        out[PL_SUM_PRESSURE_F + i] = -rhoG * (f * Sw[i] - Mw[i][1]);
        const int j = (i + 1) % 3, k = (i + 2) % 3;
        // eps_ijk X_kj = X_kj - X_jk for cyclic (i, j, k).
        out[PL_SUM_PRESSURE_T + i] =
            -rhoG * (f * (Mw[k][j] - Mw[j][k]) - (Tw[k][j] - Tw[j][k]));
        out[PL_SUM_DRAG_F + i] = 0;
        out[PL_SUM_DRAG_T + i] = 0;
    }
    out[PL_SUM_WETTED_AREA] = m->sum.w;
    out[PL_SUM_COUNT] = m->first[0].w;
}

/// The body of every buoyancy_tiles_* kernel. waterModel and withDrag are literal constants at
/// each call: the compiler drops the branches of the other water models (half the time on
/// PoCL) and, for bodies at rest in still water, the drag.
PL_INLINE void buoyancyTiles(__global const float4* positions, __global const float4* areaVectors,
                          __global const PlTile* tiles, __global const PlTileMoments* moments,
                          __global const PlBody* bodies,
                          __global const PlWave* waves, __global const float* grid,
                          int gridCountX, int gridCountZ, __global acc_t* partials,
                          __local acc_t* scratch, const int waterModel, const int withDrag) {
    const uint tileIndex = get_group_id(0);
    const uint lid = get_local_id(0);
    const PlTile tile = tiles[tileIndex];
    const PlBody body = bodies[tile.body];

    // Uniform per group: either every work-item returns here or none does.
    const float sphereBottom = dot(body.rotation[1].xyz, tile.sphere.xyz) - tile.sphere.w;
    if (sphereBottom > body.water.y) {
        if (lid < PL_SUM_SLOTS) partials[tileIndex * PL_SUM_SLOTS + lid] = 0;
        return;
    }
    // Wholly under flat water and nothing moving: the tile's moments give every sum.
    if (waterModel == PL_WATER_FLAT && !withDrag &&
        sphereBottom + 2.0f * tile.sphere.w < body.water.x) {
        if (lid == 0) submergedTileFromMoments(&body, &moments[tileIndex],
                                               partials + tileIndex * PL_SUM_SLOTS);
        return;
    }

    float sum[PL_SUM_SLOTS];
    for (int s = 0; s < PL_SUM_SLOTS; ++s) sum[s] = 0.0f;
    const float rhoG = body.fluid.x;
    const float halfRhoCd = body.fluid.y;
    const float halfRhoCf = body.fluid.z;
    // A fixed trip count (PL_ITEMS_PER_THREAD, set at build time) that the compiler unrolls.
    for (int k = 0; k < PL_ITEMS_PER_THREAD; ++k) {
        const uint i = tile.begin + k * PL_WORKGROUP_SIZE + lid;
        if (i >= tile.end) break;
        const float4 p = positions[i];
        const float3 r = rotateToWorld(&body, p.xyz);
        const float f = surfaceHeight(waterModel, &body, waves, grid, gridCountX, gridCountZ, r);
        const float depth = f - r.y;
        const float3 a = rotateToWorld(&body, areaVectors[i].xyz);
        const float wet = wetShare(depth, a, p.w);
        if (wet <= 0.0f) continue;
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
        if (!withDrag) continue;
        // Drag: pressure drag on the side facing the relative flow, optional skin friction.
        const float3 v = body.velocity.xyz + cross(body.spin.xyz, r) -
                         waterVelocity(waterModel, &body, waves, r);
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

    for (int s = 0; s < PL_SUM_SLOTS; ++s) scratch[s * PL_WORKGROUP_SIZE + lid] = sum[s];
    reduceGroup(scratch, lid, partials + tileIndex * PL_SUM_SLOTS);
}

#define PL_TILES_KERNEL(name, model, drag)                                                   \
    __kernel __attribute__((reqd_work_group_size(PL_WORKGROUP_SIZE, 1, 1))) void name(           \
        __global const float4* positions, __global const float4* areaVectors,                    \
        __global const PlTile* tiles, __global const PlTileMoments* moments,                     \
        __global const PlBody* bodies,                                                           \
        __global const PlWave* waves, __global const float* grid, int gridCountX,                \
        int gridCountZ, __global acc_t* partials) {                                              \
        __local acc_t scratch[PL_SUM_SLOTS * PL_WORKGROUP_SIZE];                                 \
        buoyancyTiles(positions, areaVectors, tiles, moments, bodies, waves, grid, gridCountX,  \
                      gridCountZ, partials, scratch, model, drag);                              \
    }

PL_TILES_KERNEL(buoyancy_tiles_flat, PL_WATER_FLAT, 1)
PL_TILES_KERNEL(buoyancy_tiles_flat_still, PL_WATER_FLAT, 0)
PL_TILES_KERNEL(buoyancy_tiles_gerstner, PL_WATER_GERSTNER, 1)
PL_TILES_KERNEL(buoyancy_tiles_gerstner_still, PL_WATER_GERSTNER, 0)
PL_TILES_KERNEL(buoyancy_tiles_heightfield, PL_WATER_HEIGHTFIELD, 1)
PL_TILES_KERNEL(buoyancy_tiles_heightfield_still, PL_WATER_HEIGHTFIELD, 0)

__kernel __attribute__((reqd_work_group_size(PL_WORKGROUP_SIZE, 1, 1)))
void reduce_bodies(__global const acc_t* partials, __global const PlBody* bodies,
                   __global acc_t* totals) {
    __local acc_t scratch[PL_SUM_SLOTS * PL_WORKGROUP_SIZE];
    const uint bodyIndex = get_group_id(0);
    const uint lid = get_local_id(0);
    const PlBody body = bodies[bodyIndex];
    acc_t sum[PL_SUM_SLOTS];
    for (int s = 0; s < PL_SUM_SLOTS; ++s) sum[s] = 0;
    for (uint t = body.tileBegin + lid; t < body.tileEnd; t += PL_WORKGROUP_SIZE)
        for (int s = 0; s < PL_SUM_SLOTS; ++s) sum[s] += partials[t * PL_SUM_SLOTS + s];
    for (int s = 0; s < PL_SUM_SLOTS; ++s) scratch[s * PL_WORKGROUP_SIZE + lid] = sum[s];
    reduceGroup(scratch, lid, totals + bodyIndex * PL_SUM_SLOTS);
}

/// Plain copy, for measuring the device's memory bandwidth (plimsoll bench).
__kernel void copy_float4(__global const float4* source, __global float4* target) {
    const size_t i = get_global_id(0);
    target[i] = source[i];
}
