#!/usr/bin/env bash
# The configuration a machine without OpenCL, CGAL or a display stack builds: the engine, the
# CLI and the tests with PLIMSOLL_WITH_OPENCL=OFF, PLIMSOLL_WITH_CGAL=OFF and
# PLIMSOLL_BUILD_EDITOR_GUI=OFF, in build-minimal/, then its tests. Tests that need OpenCL or
# CGAL skip with the reason; the ones written for this build (the device named on the command
# line is unsupported, automatic graphs say CGAL is missing) run.
#   scripts/test-minimal.sh [extra ctest arguments]
# The slowest suites run code that is the same in both configurations (the runtime library
# and its Bullet adapter, the stability grid, the runtime's install test): they are left to the full build's run, so
# this stage costs its build and about two minutes of tests. With ccache (as .ci/run sets it up)
# the build reuses the objects of earlier builds of this configuration whose inputs did not
# change. It cannot reuse the full build's: their precompiled headers differ (cmake/
# precompiled_headers.cmake says why they are on here all the same).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-minimal -G Ninja -DCMAKE_BUILD_TYPE=Release -DPLIMSOLL_WITH_OPENCL=OFF \
  -DPLIMSOLL_WITH_CGAL=OFF -DPLIMSOLL_BUILD_EDITOR_GUI=OFF "${launcher[@]}" >/dev/null
cmake --build build-minimal --parallel "$(nproc)"
built=$(date +%s)
echo "test-minimal: build took $((built - start)) s"
ctest --test-dir build-minimal --output-on-failure --parallel "$(nproc)" --output-junit "$PWD/build-minimal/ctest-junit.xml" \
  --exclude-regex '(^|/)(RuntimeConformance|RuntimeSources|BulletAdapter|StabilityGrid|StabilityEnergy|StabilityRadiation|WorldRadiation|CumminsDecay)\.|^runtime_install$' "$@"
scripts/check-skips.py build-minimal/ctest-junit.xml
echo "test-minimal: tests took $(( $(date +%s) - built )) s, total $(( $(date +%s) - start )) s"
