// Structs and constants shared by the OpenCL kernels and the C++ host code. The kernels get
// this text prepended at build time (it is embedded in the binary); C++ includes it. Every
// struct is made of 16-byte vectors and 4-byte scalars in multiples of 16 bytes, so both
// compilers lay it out identically.
#ifndef PLIMSOLL_SHARED_H
#define PLIMSOLL_SHARED_H

#ifdef __OPENCL_VERSION__
typedef float4 pl_float4;
typedef int pl_int;
typedef uint pl_uint;
#else
#include <cstdint>
namespace plimsoll::gpu {
struct alignas(16) pl_float4 {
    float x, y, z, w;
};
using pl_int = std::int32_t;
using pl_uint = std::uint32_t;
#endif

/// Work-items per work-group. A tile (one work-group's share) holds PL_WORKGROUP_SIZE times
/// PL_ITEMS_PER_THREAD entries; the host picks the items per thread for the device and passes
/// it to the kernel build.
#define PL_WORKGROUP_SIZE 128

#define PL_WATER_FLAT 0
#define PL_WATER_GERSTNER 1
#define PL_WATER_HEIGHTFIELD 2
#define PL_MAX_WAVES 16

/// Slots of one body's sums (a tile's partial, then the body's total).
#define PL_SUM_VOLUME 0             /* sum A_y (y - f)                         m^3   */
#define PL_SUM_MOMENT 1             /* 3: first moments of the submerged volume m^4   */
#define PL_SUM_PRESSURE_F 4         /* 3: -sum p A                             N     */
#define PL_SUM_PRESSURE_T 7         /* 3: sum r x (-p A)                       N m   */
#define PL_SUM_DRAG_F 10            /* 3                                       N     */
#define PL_SUM_DRAG_T 13            /* 3                                       N m   */
#define PL_SUM_WETTED_AREA 16       /*                                         m^2   */
#define PL_SUM_COUNT 17             /* submerged entries                             */
#define PL_SUM_TILES_DRY 18         /* tiles found dry under the water's local quadratic   */
#define PL_SUM_TILES_CLOSED 19      /* tiles whose hydrostatics came from their moments    */
#define PL_SUM_TILES_DRAG_CLOSED 20 /* tiles whose drag came from their moments       */
#define PL_SUM_SLOTS 21

/// One body for one frame, everything relative to its centre of mass c (world axes), so that
/// single precision keeps its digits wherever the body is.
typedef struct {
    pl_float4 rotation[3]; /* rows of R (object -> world)                            */
    pl_float4 velocity;    /* xyz: velocity of c, m/s                                 */
    pl_float4 spin;        /* xyz: angular velocity, rad/s                            */
    pl_float4 water;       /* x: mean level - c.y (m); y: highest surface - c.y (m);  */
                           /* z: largest misfit (m) of a tile's water quadratic that  */
                           /*    still takes the closed form on waves (0: none does)  */
    pl_float4 fluid;       /* x: rho g; y: rho C_d / 2; z: rho C_f / 2; w: rho        */
    pl_float4 grid;        /* height field: x, z fraction of c's cell; 1/spacing      */
    pl_int waterModel;     /* PL_WATER_*                                              */
    pl_int waveBegin;      /* first wave in the wave buffer                           */
    pl_int waveCount;
    pl_int gridCellX; /* height field: integer cell of c                         */
    pl_int gridCellZ;
    pl_int padding[3]; /* to a multiple of 16 bytes, as the float4s align it      */
} PlBody;

/// One Gerstner wave as seen from one body: phase = k D.c_xz - omega t + phi (mod 2 pi).
typedef struct {
    float amplitude;  /* m                                  */
    float wavenumber; /* k, 1/m                             */
    float omega;      /* rad/s                              */
    float q;          /* horizontal displacement factor Q_i */
    float directionX;
    float directionZ;
    float phase; /* rad                                */
    float padding;
} PlWave;

/// A run of consecutive texel entries of one body, with a bounding sphere for culling and the
/// cone of its normals (for the sign of the drag's A.v over the whole tile).
typedef struct {
    pl_uint body;
    pl_uint begin;
    pl_uint end;
    pl_uint padding;
    pl_float4 sphere; /* xyz: centre t relative to c, object space (m); w: radius (m), every */
                      /* entry's half side included                                       */
    pl_float4 cone;   /* xyz: mean normal (object space); w: cosine of the widest angle of  */
                      /* a normal from it (-1: no cone)                                     */
} PlTile;

/// Moments of a tile's area vectors a about its centre t (s = p - t, object space), so that a
/// tile lying wholly under the water costs a few hundred operations instead of a pass over
/// its texels: under a water quadratic the hydrostatic sums are polynomials of degree two in s
/// (and one of degree three, from the third moments), and the drag of a tile that faces the
/// flow throughout one of degree three (docs/design.md, "Compute backends"). Symmetric index
/// sets are stored once, in the order of plimsoll_eval's kPair and kTriple: (jk) = 00 01 02 11
/// 12 22 and (jkl) = 000 001 002 011 012 022 111 112 122 222.
typedef struct {
    pl_float4 sum;      /* xyz: sum a; w: sum of areas                    */
    pl_float4 first[3]; /* [i].xyz: sum a_i s; [0].w: entry count         */
    float second[18];   /* [6 i + (jk)]: sum a_i s_j s_k                  */
    float third[30];    /* [10 i + (jkl)]: sum a_i s_j s_k s_l            */
} PlTileMoments;

#ifndef __OPENCL_VERSION__
}  // namespace plimsoll::gpu
#endif

#endif
