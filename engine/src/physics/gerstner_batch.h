// Gerstner heights and velocities at many points in one call (WaterModel::heights and
// ::velocities): the same fixed-point search and sums as WaterModel::height and ::velocity
// (water.cpp, the reference the kernels mirror), with the phases formed and reduced to
// [-pi, pi] in double and their sines and cosines taken in single precision, eight or four
// points at a time (xsimd). The single-precision trigonometry changes a height by at most a
// few 1e-7 of the amplitudes (tests/physics/test_water.cpp measures it against the reference).
//
// Built three times: for the x86-64 baseline (SSE2), for AVX2 with FMA (8 points a block) and
// for AVX-512 (16), chosen at run time (gerstnerBatchIsa), so that one binary runs on any x86-64
// and uses the wider units where they exist.
#pragma once

#include <cstddef>

namespace plimsoll::detail {

/// One wave's constants (WaterModel's termsOf), with the per-call phase folded in.
struct GerstnerBatchWave {
    double amplitude;  ///< A, m
    double k;          ///< wavenumber, 1/m
    double omega;      ///< angular frequency, rad/s
    double qa;         ///< Q A: the horizontal displacement's amplitude, m
    double dx, dz;     ///< unit direction
    double phase0;     ///< phase - omega t, reduced to [-pi, pi]
};

struct GerstnerBatch {
    const GerstnerBatchWave* waves;
    std::size_t count;
    double level;
};

/// n heights into out[i].
void gerstnerHeightsBaseline(const GerstnerBatch& g, std::size_t n, const double* x,
                             const double* z, double* out);
void gerstnerHeightsAvx2(const GerstnerBatch& g, std::size_t n, const double* x, const double* z,
                         double* out);
void gerstnerHeightsAvx512(const GerstnerBatch& g, std::size_t n, const double* x, const double* z,
                           double* out);
/// n velocities into out[3 i + 0..2].
void gerstnerVelocitiesBaseline(const GerstnerBatch& g, std::size_t n, const double* x,
                                const double* y, const double* z, double* out);
void gerstnerVelocitiesAvx2(const GerstnerBatch& g, std::size_t n, const double* x, const double* y,
                            const double* z, double* out);
void gerstnerVelocitiesAvx512(const GerstnerBatch& g, std::size_t n, const double* x,
                              const double* y, const double* z, double* out);

/// The builds, narrowest first.
enum class GerstnerIsa { baseline, avx2, avx512 };

/// The widest build this processor runs (checked once). AVX-512 is taken only where the
/// processor also has AVX-512 VBMI2, which marks Intel's Ice Lake and later and AMD's Zen 4 and
/// later: on the Skylake-era server parts before them, 512-bit arithmetic lowers the core's
/// clock for a while after it, for the whole program, and a few microseconds of waves are not
/// worth that.
GerstnerIsa gerstnerBatchWidest();
/// The build WaterModel::heights and ::velocities use: the widest, unless set narrower (the
/// tests compare every build this processor runs with the one-point reference).
GerstnerIsa gerstnerBatchIsa();
/// Sets it, clamped to the widest (for tests; thread-safe, but meant to be set before use).
void setGerstnerBatchIsa(GerstnerIsa isa);

/// One build's entry points (the functions above of one suffix).
struct GerstnerBatchBuild {
    void (*heights)(const GerstnerBatch& g, std::size_t n, const double* x, const double* z,
                    double* out);
    void (*velocities)(const GerstnerBatch& g, std::size_t n, const double* x, const double* y,
                       const double* z, double* out);
};
/// The entry points of the build in use (gerstnerBatchIsa).
const GerstnerBatchBuild& gerstnerBatchBuild();

}  // namespace plimsoll::detail
