// Water-graph exchange through the permeable texels (paper 4.2): one pass over a body's
// permeable samples, each work-group summing its samples per node. buoyancy.cl comes before
// this file (PlBody, surfaceHeight, acc_t). The C++ reference is
// engine/src/graph/exchange_reference.cpp; tests hold this file against it.
//
// Per sample (position relative to the frame's centre c, object axes; w = permeability x
// area): r = R p, outside depth d_out = max(0, f(r) - r.y), inside head d_in = max(0, s_n -
// r.y) with s_n the node's water surface (relative to c.y), h = d_out - d_in, and
// |q| = factor w |h| (linear) or factor w sqrt|h| (Torricelli). The group writes, per node,
// the inflow, the outflow and the highest outside surface of its inflowing samples.
//
// The outside surface f is the water's on the exchange's world lattice (plimsoll_eval
// kExchangeLatticeSpacing s), interpolated bilinearly in the sample's cell, as the C++ takes
// it (exchangeSurfaces). `lattice`: xy, c's x and z in lattice units less their floor (so the
// cell is found without c's large coordinates in single precision); z: 1/s; w: s.

PL_INLINE void exchangeGroup(const int waterModel, __global const float4* samples,
                             __global const uint* nodes, uint count,
                             __global const PlBody* frame, __global const PlWave* waves,
                             __global const float* grid, int gridCountX, int gridCountZ,
                             __global const float* surfaces, float4 lattice, float factor,
                             int torricelli, uint nodeCount, __global acc_t* partials, __local float* inflow,
                             __local float* outflow, __local float* top, __local uint* node) {
    const uint lid = get_local_id(0);
    const uint i = get_global_id(0);
    const PlBody body = frame[0];
    float qin = 0.0f, qout = 0.0f, f = -INFINITY;
    uint n = 0xffffffffu;
    if (i < count) {
        const float4 s = samples[i];
        const float3 r = rotateToWorld(&body, s.xyz);
        float surface;
        if (waterModel == PL_WATER_FLAT) {
            surface = surfaceHeight(waterModel, &body, waves, grid, gridCountX, gridCountZ, r);
        } else {
            const float gx = lattice.x + r.x * lattice.z, gz = lattice.y + r.z * lattice.z;
            const float cx = floor(gx), cz = floor(gz);
            const float tx = gx - cx, tz = gz - cz;
            const float x0 = (cx - lattice.x) * lattice.w, x1 = (cx + 1.0f - lattice.x) * lattice.w;
            const float z0 = (cz - lattice.y) * lattice.w, z1 = (cz + 1.0f - lattice.y) * lattice.w;
            const float f00 = surfaceHeight(waterModel, &body, waves, grid, gridCountX,
                                            gridCountZ, (float3)(x0, r.y, z0));
            const float f10 = surfaceHeight(waterModel, &body, waves, grid, gridCountX,
                                            gridCountZ, (float3)(x1, r.y, z0));
            const float f01 = surfaceHeight(waterModel, &body, waves, grid, gridCountX,
                                            gridCountZ, (float3)(x0, r.y, z1));
            const float f11 = surfaceHeight(waterModel, &body, waves, grid, gridCountX,
                                            gridCountZ, (float3)(x1, r.y, z1));
            const float a = f00 + tx * (f10 - f00), b = f01 + tx * (f11 - f01);
            surface = a + tz * (b - a);
        }
        n = nodes[i];
        const float head = fmax(0.0f, surface - r.y) - fmax(0.0f, surfaces[n] - r.y);
        const float q = torricelli ? factor * s.w * sqrt(fabs(head)) : factor * s.w * fabs(head);
        if (head > 0.0f) {
            qin = q;
            f = surface;
        } else if (head < 0.0f) {
            qout = q;
        }
    }
    inflow[lid] = qin;
    outflow[lid] = qout;
    top[lid] = f;
    node[lid] = n;
    barrier(CLK_LOCAL_MEM_FENCE);
    // One work-item per node sums the group's samples of that node (samples are sorted by
    // node, so a group spans few), in acc_t.
    for (uint k = lid; k < nodeCount; k += PL_WORKGROUP_SIZE) {
        acc_t a = 0, b = 0;
        float t = -INFINITY;
        for (uint j = 0; j < PL_WORKGROUP_SIZE; ++j) {
            if (node[j] != k) continue;
            a += inflow[j];
            b += outflow[j];
            t = fmax(t, top[j]);
        }
        __global acc_t* out = partials + (get_group_id(0) * nodeCount + k) * 3;
        out[0] = a;
        out[1] = b;
        out[2] = t;
    }
}

#define PL_EXCHANGE_KERNEL(name, model)                                                        \
    __kernel __attribute__((reqd_work_group_size(PL_WORKGROUP_SIZE, 1, 1))) void name(           \
        __global const float4* samples, __global const uint* nodes, uint count,                  \
        __global const PlBody* frame, __global const PlWave* waves, __global const float* grid,  \
        int gridCountX, int gridCountZ, __global const float* surfaces, float4 lattice,          \
        float factor, int torricelli, uint nodeCount, __global acc_t* partials) {                \
        __local float inflow[PL_WORKGROUP_SIZE], outflow[PL_WORKGROUP_SIZE],                     \
            top[PL_WORKGROUP_SIZE];                                                               \
        __local uint node[PL_WORKGROUP_SIZE];                                                     \
        exchangeGroup(model, samples, nodes, count, frame, waves, grid, gridCountX, gridCountZ,  \
                      surfaces, lattice, factor, torricelli, nodeCount, partials, inflow,        \
                      outflow, top, node);                                                       \
    }

PL_EXCHANGE_KERNEL(graph_exchange_flat, PL_WATER_FLAT)
PL_EXCHANGE_KERNEL(graph_exchange_gerstner, PL_WATER_GERSTNER)
PL_EXCHANGE_KERNEL(graph_exchange_heightfield, PL_WATER_HEIGHTFIELD)
