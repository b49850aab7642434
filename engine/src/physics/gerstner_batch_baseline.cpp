// The batched Gerstner evaluation for the x86-64 baseline (gerstner_batch.h).
#include "gerstner_batch.h"

#include <xsimd/xsimd.hpp>

#include <algorithm>

namespace plimsoll::detail {

#include "gerstner_batch_impl.h"

PLIMSOLL_GERSTNER_BATCH_ENTRY_POINTS(Baseline)

bool gerstnerBatchUsesAvx2() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return avx2;
#else
    return false;
#endif
}

}  // namespace plimsoll::detail
