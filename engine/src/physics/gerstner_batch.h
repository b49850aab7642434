// Gerstner heights and velocities at many points in one call (WaterModel::heights and
// ::velocities): the same fixed-point search and sums as WaterModel::height and ::velocity
// (water.cpp, the reference the kernels mirror), with the phases formed and reduced to
// [-pi, pi] in double and their sines and cosines taken in single precision, eight or four
// points at a time (xsimd). The single-precision trigonometry changes a height by at most a
// few 1e-7 of the amplitudes (tests/physics/test_water.cpp measures it against the reference).
//
// Built twice: for the x86-64 baseline (SSE2) and for AVX2 with FMA, chosen at run time
// (gerstnerBatchIsa), so that one binary runs on any x86-64 and uses the wider units where
// they exist.
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
void gerstnerHeightsBaseline(const GerstnerBatch& g, std::size_t n, const double* x, const double* z, double* out);
void gerstnerHeightsAvx2(const GerstnerBatch& g, std::size_t n, const double* x, const double* z, double* out);
/// n velocities into out[3 i + 0..2].
void gerstnerVelocitiesBaseline(const GerstnerBatch& g, std::size_t n, const double* x, const double* y,
                                const double* z, double* out);
void gerstnerVelocitiesAvx2(const GerstnerBatch& g, std::size_t n, const double* x, const double* y,
                            const double* z, double* out);

/// Whether this processor runs the AVX2 build (checked once).
bool gerstnerBatchUsesAvx2();

}  // namespace plimsoll::detail
