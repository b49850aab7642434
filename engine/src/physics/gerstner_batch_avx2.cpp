// The batched Gerstner evaluation for AVX2 with FMA (gerstner_batch.h). This file alone is
// compiled with -mavx2 -mfma (engine/CMakeLists.txt) and runs only where
// gerstnerBatchIsa() says so; everything it compiles is internal to it.
#include "gerstner_batch.h"

#include <xsimd/xsimd.hpp>

#include <algorithm>

namespace plimsoll::detail {

#include "gerstner_batch_impl.h"

PLIMSOLL_GERSTNER_BATCH_ENTRY_POINTS(Avx2)

}  // namespace plimsoll::detail
