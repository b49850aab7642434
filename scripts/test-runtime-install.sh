#!/usr/bin/env bash
# Installs the runtime library (engine/runtime) on its own into temporary prefixes, static and
# shared, and builds fresh game projects against each: the float_body example (C) and the
# consumers of tests/runtime/consumer (C and C++), with find_package(PlimsollRuntime) and with
# pkg-config. Exports a fresh bundle of projects/buoy.plim.json with build/editor/plimsoll and
# floats it with each. Checks that the shared library exports the C ABI and nothing else and
# that nothing links OpenEXR. Exits non-zero on any failure.
# Usage: scripts/test-runtime-install.sh [PLIMSOLL_EXECUTABLE]
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
plimsoll=${1:-$root/build/editor/plimsoll}
if [[ ! -x "$plimsoll" ]]; then
  echo "test-runtime-install: $plimsoll not found (build the project first)" >&2
  exit 1
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# shellcheck source=scripts/standalone-cmake.sh
source scripts/standalone-cmake.sh
start=$(date +%s)

echo "== runtime: configure, build, install to $work/prefix"
cmake -S engine/runtime -B "$work/runtime-build" "${generator[@]}" "${launcher[@]}" \
  -DCMAKE_BUILD_TYPE=Release >"$work/runtime-configure.log" || { cat "$work/runtime-configure.log"; exit 1; }
cmake --build "$work/runtime-build" --parallel 2
cmake --install "$work/runtime-build" --prefix "$work/prefix" >/dev/null
for f in include/plimsoll_runtime.h include/plimsoll_runtime/runtime.hpp \
         include/plimsoll_eval/graph_settings.hpp \
         lib/cmake/PlimsollRuntime/PlimsollRuntimeConfig.cmake \
         lib/cmake/PlimsollRuntime/PlimsollRuntimeConfigVersion.cmake lib/pkgconfig/plimsoll_runtime.pc; do
  [[ -f "$work/prefix/$f" ]] || { echo "test-runtime-install: $f not installed" >&2; exit 1; }
done

echo "== example: configure and build against the installed package"
cmake -S engine/runtime/examples/float_body -B "$work/example-build" "${generator[@]}" "${launcher[@]}" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" >"$work/example-configure.log" \
  || { cat "$work/example-configure.log"; exit 1; }
cmake --build "$work/example-build"

echo "== export projects/buoy.plim.json and float it"
"$plimsoll" export projects/buoy.plim.json --out "$work/bundles" --quiet >/dev/null
bundle=$(dirname "$(find "$work/bundles" -name manifest.json | head -n 1)")
[[ -d "$bundle" ]] || { echo "test-runtime-install: no bundle exported" >&2; exit 1; }
"$work/example-build/float_body" "$bundle" 10

# A damaged bundle must be refused with the file named.
printf 'x' >>"$bundle/samples.exr"
if "$work/example-build/float_body" "$bundle" 1 2>"$work/err.txt"; then
  echo "test-runtime-install: a damaged bundle was accepted" >&2
  exit 1
fi
grep -q "samples.exr" "$work/err.txt" || { echo "test-runtime-install: error does not name the file:" >&2; cat "$work/err.txt" >&2; exit 1; }
"$plimsoll" export projects/buoy.plim.json --out "$work/bundles" --quiet >/dev/null  # undamaged again

# A fresh C and C++ project against a prefix, with find_package and with pkg-config; each
# floats the bundle. $1: prefix, $2: label.
consumers() {
  local prefix=$1 label=$2
  for language in C CXX; do
    echo "== $label: $language consumer with find_package"
    cmake -S tests/runtime/consumer -B "$work/$label-$language" "${generator[@]}" "${launcher[@]}" \
      -DCMAKE_BUILD_TYPE=Release -DCONSUMER_LANGUAGE=$language -DCMAKE_PREFIX_PATH="$prefix" \
      >"$work/$label-$language.log" || { cat "$work/$label-$language.log"; exit 1; }
    cmake --build "$work/$label-$language" >/dev/null
    "$work/$label-$language/consumer" "$bundle"
    if ldd "$work/$label-$language/consumer" | grep -qi openexr; then
      echo "test-runtime-install: $label $language consumer links OpenEXR" >&2; exit 1
    fi
  done
  echo "== $label: C and C++ consumers with pkg-config"
  local flags rpath=()
  flags=$(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs plimsoll_runtime)
  [[ $label == shared ]] && rpath=(-Wl,-rpath,"$prefix/lib")
  # shellcheck disable=SC2086
  cc -std=c11 tests/runtime/consumer/consumer.c -o "$work/$label-pc-c" $flags "${rpath[@]}"
  # shellcheck disable=SC2086
  c++ -std=c++17 tests/runtime/consumer/consumer.cpp -o "$work/$label-pc-cxx" $flags "${rpath[@]}"
  "$work/$label-pc-c" "$bundle"
  "$work/$label-pc-cxx" "$bundle"
}
consumers "$work/prefix" static

# The Bullet adapter installed as source: a game compiles it with its own Bullet against the
# installed runtime (here Debian's libbullet-dev), and the harbour example floats the buoy.
if pkg-config --exists bullet; then
  echo "== Bullet adapter from the installed sources"
  adapter="$work/prefix/share/plimsoll_runtime/adapters/bullet"
  # shellcheck disable=SC2046
  c++ -std=c++17 -O1 "$adapter/harbour.cpp" "$adapter/plimsoll_bullet.cpp" -I"$adapter" -o "$work/harbour" \
    $(PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig" pkg-config --cflags --libs plimsoll_runtime bullet)
  "$work/harbour" "$bundle" 2 | tail -n 2
else
  echo "test-runtime-install: libbullet-dev not installed: the installed Bullet adapter is not compiled"
fi
# The Jolt guide's header ships beside it (compiled by tests/adapters/jolt where JOLT_DIR is set).
[[ -f "$work/prefix/share/plimsoll_runtime/examples/jolt/plimsoll_jolt.hpp" ]] \
  || { echo "test-runtime-install: the Jolt guide's plimsoll_jolt.hpp is not installed" >&2; exit 1; }

echo "== runtime: shared library, installed to $work/shared"
cmake -S engine/runtime -B "$work/runtime-shared" "${generator[@]}" "${launcher[@]}" \
  -DCMAKE_BUILD_TYPE=Release -DPLIMSOLL_RUNTIME_SHARED=ON >"$work/shared-configure.log" \
  || { cat "$work/shared-configure.log"; exit 1; }
cmake --build "$work/runtime-shared" --parallel 2 --target plimsoll_runtime
cmake --install "$work/runtime-shared" --prefix "$work/shared" >/dev/null
library=$(find "$work/shared/lib" -name 'libplimsoll_runtime.so.*' -type f | head -n 1)
[[ -f "$library" ]] || { echo "test-runtime-install: no shared library installed" >&2; exit 1; }
# The shared library exports the C ABI only: every defined dynamic symbol is plimsoll_*.
others=$(nm -D --defined-only "$library" | awk '{print $3}' | grep -v '^plimsoll_' | grep -v '^_init$\|^_fini$' || true)
if [[ -n "$others" ]]; then
  echo "test-runtime-install: the shared library exports more than its C ABI:" >&2
  echo "$others" | head -20 >&2
  exit 1
fi
echo "shared library: $(nm -D --defined-only "$library" | grep -c ' plimsoll_') plimsoll_ symbols, nothing else"
consumers "$work/shared" shared
echo "== ok ($(( $(date +%s) - start )) s)"
