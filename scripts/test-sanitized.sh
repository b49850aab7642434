#!/usr/bin/env bash
# The whole test suite built with AddressSanitizer and UndefinedBehaviorSanitizer (gcc,
# PLIMSOLL_SANITIZE=ON, build-asan/): any memory error, leak or undefined behaviour fails the
# test that hit it (-fno-sanitize-recover=all).
#   scripts/test-sanitized.sh [extra ctest arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
start=$(date +%s)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DPLIMSOLL_SANITIZE=ON "${launcher[@]}" >/dev/null
cmake --build build-asan --parallel "$(nproc)"
built=$(date +%s)
echo "test-sanitized: build took $((built - start)) s"

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0"
ctest --test-dir build-asan --output-on-failure --parallel "$(nproc)" --output-junit "$PWD/build-asan/ctest-junit.xml" "$@"
scripts/check-skips.py build-asan/ctest-junit.xml
echo "test-sanitized: tests took $(( $(date +%s) - built )) s, total $(( $(date +%s) - start )) s"
