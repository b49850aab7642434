#!/usr/bin/env bash
# The second configuration CI builds, and the sanitizers: the engine, the CLI and the tests as a
# machine without OpenCL, CGAL or a display stack builds them (PLIMSOLL_WITH_OPENCL=OFF,
# PLIMSOLL_WITH_CGAL=OFF, PLIMSOLL_BUILD_EDITOR_GUI=OFF), compiled with AddressSanitizer and
# UndefinedBehaviorSanitizer (g++, PLIMSOLL_SANITIZE=ON, build-asan/), then its tests. Any memory
# error, leak or undefined behaviour fails the test that hit it (-fno-sanitize-recover=all);
# tests that need OpenCL, CGAL or a window skip with the reason, and the ones written for this
# configuration (the device named on the command line is unsupported, automatic graphs say
# CGAL is missing) run.
#   scripts/test-sanitized.sh [extra ctest arguments]
# One build for both, because a cold CI run on 2 cores has room for two builds besides the
# fuzzers' (the README's "Tests, fuzzing, sanitizers" gives the figures). What the sanitizers
# do not see here: CGAL's repair and segmentation, the OpenCL hosts and the editor window; the
# full build's run covers their results, and the fuzzers the loaders in front of them.
# The long simulations below check numbers, not memory: their code is the same per step as the
# short ones that do run here, and they run in the full build.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
start=$(date +%s)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DPLIMSOLL_SANITIZE=ON \
  -DPLIMSOLL_WITH_OPENCL=OFF -DPLIMSOLL_WITH_CGAL=OFF -DPLIMSOLL_BUILD_EDITOR_GUI=OFF \
  "${launcher[@]}" >/dev/null
cmake --build build-asan --parallel "$(nproc)"
built=$(date +%s)
echo "test-sanitized: build took $((built - start)) s"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0"
ctest --test-dir build-asan --output-on-failure --parallel "$(nproc)" \
  --output-junit "$PWD/build-asan/ctest-junit.xml" \
  --exclude-regex '(^|/)(StabilityGrid|StabilityEnergy|StabilityRadiation|CumminsDecay)\.' "$@"
scripts/check-skips.py build-asan/ctest-junit.xml
echo "test-sanitized: tests took $(( $(date +%s) - built )) s, total $(( $(date +%s) - start )) s"
