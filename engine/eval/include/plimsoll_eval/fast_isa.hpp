// Which instruction set the fast evaluation runs (fast.hpp, fast_leaves.hpp).
//
// The evaluation is compiled twice: for the target's baseline and, on x86-64 with GCC or Clang,
// for AVX2 (a function attribute that inlines everything the evaluation calls, so that nothing
// outside it is built for AVX2), and the second runs where the processor has it
// (cpuHasAvx2Fma). Without fused multiply-adds the two give the same bits: the lanes of every
// sum are explicit and no operation is reassociated, so only the vector width differs
// (tests/runtime/test_runtime_determinism.cpp compares them). PLIMSOLL_EVAL_FMA builds the
// AVX2 variant with FMA too, whose products round once: faster where it pays, and no longer
// the baseline's bits.
#pragma once

#if (defined(__x86_64__) || defined(_M_X64)) && (defined(__GNUC__) || defined(__clang__))
#define PLIMSOLL_EVAL_AVX2_LOOPS 1
#ifdef PLIMSOLL_EVAL_FMA
#define PLIMSOLL_EVAL_AVX2_TARGET __attribute__((target("avx2,fma"), flatten))
#else
#define PLIMSOLL_EVAL_AVX2_TARGET __attribute__((target("avx2"), flatten))
#endif
#endif

#include <cstdlib>
#include <string_view>
#include <type_traits>

namespace plimsoll_eval {

/// Whether the AVX2 builds of the evaluation run (checked once): where the processor has AVX2
/// and FMA, unless the environment variable PLIMSOLL_ISA is "baseline" (the instruction-set
/// switch the determinism tests and docs/c-abi.md use).
inline bool cpuHasAvx2Fma() {
#ifdef PLIMSOLL_EVAL_AVX2_LOOPS
    static const bool has = [] {
        const char* forced = std::getenv("PLIMSOLL_ISA");
        if (forced && std::string_view(forced) == "baseline") return false;
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    }();
    return has;
#else
    return false;
#endif
}

/// Calls f with `flag` as a compile-time constant (std::true_type or std::false_type), so that
/// a run-time choice picks one of a template's instances without writing each call out.
template <class F>
inline void withFlag(bool flag, F f) {
    if (flag)
        f(std::true_type{});
    else
        f(std::false_type{});
}

}  // namespace plimsoll_eval
