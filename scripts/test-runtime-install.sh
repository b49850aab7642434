#!/usr/bin/env bash
# Installs the runtime library (engine/runtime) on its own into a temporary prefix, builds the
# float_body example against it with find_package(PlimsollRuntime), exports a fresh bundle of
# projects/buoy.plim.json with build/editor/plimsoll and floats it. Exits non-zero on any
# failure. Usage: scripts/test-runtime-install.sh [PLIMSOLL_EXECUTABLE]
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
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
launcher=()
command -v ccache >/dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
start=$(date +%s)

echo "== runtime: configure, build, install to $work/prefix"
cmake -S engine/runtime -B "$work/runtime-build" "${generator[@]}" "${launcher[@]}" \
  -DCMAKE_BUILD_TYPE=Release >"$work/runtime-configure.log" || { cat "$work/runtime-configure.log"; exit 1; }
cmake --build "$work/runtime-build" --parallel 2
cmake --install "$work/runtime-build" --prefix "$work/prefix" >/dev/null
for f in include/plimsoll_runtime.h include/plimsoll_runtime/runtime.hpp \
         lib/cmake/PlimsollRuntime/PlimsollRuntimeConfig.cmake \
         lib/cmake/PlimsollRuntime/PlimsollRuntimeConfigVersion.cmake; do
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
echo "== ok ($(( $(date +%s) - start )) s)"
