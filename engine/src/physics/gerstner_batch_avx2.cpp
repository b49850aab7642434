// The batched Gerstner evaluation for AVX2 with FMA (gerstner_batch.h). This file alone is
// compiled with -mavx2 -mfma (engine/CMakeLists.txt) and runs only where
// gerstnerBatchUsesAvx2() says so; everything it compiles is internal to it.
#include "gerstner_batch.h"

#include <xsimd/xsimd.hpp>

#include <algorithm>

namespace plimsoll::detail {
namespace {
#include "gerstner_batch_impl.h"
}  // namespace

void gerstnerHeightsAvx2(const GerstnerBatch& g, std::size_t n, const double* x, const double* z, double* out) {
    heightsImpl(g, n, x, z, out);
}

void gerstnerVelocitiesAvx2(const GerstnerBatch& g, std::size_t n, const double* x, const double* y,
                            const double* z, double* out) {
    velocitiesImpl(g, n, x, y, z, out);
}

}  // namespace plimsoll::detail
