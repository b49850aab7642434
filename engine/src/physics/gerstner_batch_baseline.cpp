// The batched Gerstner evaluation for the x86-64 baseline (gerstner_batch.h).
#include "gerstner_batch.h"

#include <xsimd/xsimd.hpp>

#include <algorithm>
#include <atomic>

namespace plimsoll::detail {

#include "gerstner_batch_impl.h"

PLIMSOLL_GERSTNER_BATCH_ENTRY_POINTS(Baseline)

GerstnerIsa gerstnerBatchWidest() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    static const GerstnerIsa widest = [] {
#ifdef PLIMSOLL_GERSTNER_AVX512
        if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
            __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
            __builtin_cpu_supports("avx512vbmi2"))
            return GerstnerIsa::avx512;
#endif
#ifdef PLIMSOLL_GERSTNER_AVX2
        if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
            return GerstnerIsa::avx2;
#endif
        return GerstnerIsa::baseline;
    }();
    return widest;
#else
    return GerstnerIsa::baseline;
#endif
}

namespace {
/// The build in use; -1: not set (the widest).
std::atomic<int> chosenIsa{-1};
}  // namespace

GerstnerIsa gerstnerBatchIsa() {
    const int chosen = chosenIsa.load(std::memory_order_relaxed);
    return chosen < 0 ? gerstnerBatchWidest() : static_cast<GerstnerIsa>(chosen);
}

void setGerstnerBatchIsa(GerstnerIsa isa) {
    chosenIsa.store(static_cast<int>(std::min(isa, gerstnerBatchWidest())),
                    std::memory_order_relaxed);
}

const GerstnerBatchBuild& gerstnerBatchBuild() {
    // By GerstnerIsa; a build this compiler did not make is never the widest, and takes the
    // baseline's place in the table.
    static constexpr GerstnerBatchBuild builds[] = {
        {gerstnerHeightsBaseline, gerstnerVelocitiesBaseline},
#ifdef PLIMSOLL_GERSTNER_AVX2
        {gerstnerHeightsAvx2, gerstnerVelocitiesAvx2},
#else
        {gerstnerHeightsBaseline, gerstnerVelocitiesBaseline},
#endif
#ifdef PLIMSOLL_GERSTNER_AVX512
        {gerstnerHeightsAvx512, gerstnerVelocitiesAvx512},
#else
        {gerstnerHeightsBaseline, gerstnerVelocitiesBaseline},
#endif
    };
    return builds[static_cast<int>(gerstnerBatchIsa())];
}

}  // namespace plimsoll::detail
