// The batched Gerstner evaluation for AVX-512 (gerstner_batch.h): 16 points a block. This file
// alone is compiled with -mavx512f -mavx512dq -mavx512vl -mavx512bw (engine/CMakeLists.txt)
// and runs only where gerstnerBatchIsa() says so; everything it compiles is internal to it.
#include "gerstner_batch.h"

#include <xsimd/xsimd.hpp>

#include <algorithm>

namespace plimsoll::detail {

#include "gerstner_batch_impl.h"

PLIMSOLL_GERSTNER_BATCH_ENTRY_POINTS(Avx512)

}  // namespace plimsoll::detail
