#!/usr/bin/env bash
# Builds the runtime for the web (web/README.md): the WebAssembly module with Debian's emscripten
# (emcmake, em++) into build-web/wasm, copied to web/package/plimsoll.wasm, and the native side of
# the package's tests (the runtime from the same sources with the same math, float_body and
# plimsoll_web_reference) into build-web/native, and the viewer page (web/viewer with three.js
# from npm, installed from its package-lock.json) into build-web/viewer, which `plimsoll export
# --web` copies. Exits 77 where emscripten is not installed.
# Usage: scripts/build-web.sh [--wasm-only]
set -euo pipefail
cd "$(dirname "$0")/.."
command -v emcmake >/dev/null 2>&1 && command -v em++ >/dev/null 2>&1 || {
  echo "build-web: emscripten (emcmake, em++) not installed: scripts/install-deps.sh installs it" >&2
  exit 77
}
# shellcheck source=scripts/standalone-cmake.sh
source scripts/standalone-cmake.sh
start=$(date +%s)
log=build-web/build.log
mkdir -p build-web
: >"$log"
# Emscripten keeps its cache of system libraries under its own folder, which may not be writable:
# a private copy then (the libraries are built once into it).
if [[ -z "${EM_CACHE:-}" ]] && ! [[ -w "$(em-config CACHE 2>/dev/null || echo /nonexistent)" ]]; then
  export EM_CACHE=$PWD/build-web/em-cache
fi
echo "== build-web: WebAssembly module (emscripten $(emcc --version | head -n 1 | sed 's/.* \([0-9][0-9.]*\) .*/\1/'))"
emcmake cmake -S web -B build-web/wasm "${generator[@]}" "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release >>"$log" 2>&1 \
  || { tail -30 "$log"; exit 1; }
cmake --build build-web/wasm --parallel 2 >>"$log" 2>&1 || { tail -40 "$log"; exit 1; }
cp build-web/wasm/plimsoll.wasm web/package/plimsoll.wasm
if [[ "${1:-}" != --wasm-only ]]; then
  echo "== build-web: native runtime with the same math, float_body, plimsoll_web_reference"
  cmake -S web/native -B build-web/native "${generator[@]}" "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release >>"$log" 2>&1 \
    || { tail -30 "$log"; exit 1; }
  cmake --build build-web/native --parallel 2 --target plimsoll_float_body plimsoll_web_reference plimsoll_web_bench >>"$log" 2>&1 \
    || { tail -40 "$log"; exit 1; }
fi
if [[ "${1:-}" != --wasm-only ]]; then
  if command -v npm >/dev/null 2>&1; then
    echo "== build-web: viewer page (three.js from web/viewer/package-lock.json)"
    if [[ ! -f web/viewer/node_modules/three/package.json ||
          web/viewer/package-lock.json -nt web/viewer/node_modules/three/package.json ]]; then
      (cd web/viewer && npm ci --no-audit --no-fund --loglevel=error >>"../../$log" 2>&1) || { tail -20 "$log"; exit 1; }
    fi
    viewer=build-web/viewer
    rm -rf "$viewer"
    three=web/viewer/node_modules/three
    mkdir -p "$viewer/vendor/three/build" "$viewer/vendor/three/examples/jsm/loaders" \
      "$viewer/vendor/three/examples/jsm/utils" "$viewer/vendor/three/examples/jsm/controls" "$viewer/vendor/plimsoll-runtime"
    cp web/viewer/index.html web/viewer/viewer.js "$viewer/"
    cp "$three/LICENSE" "$viewer/vendor/three/"
    cp "$three/build/three.module.js" "$viewer/vendor/three/build/"
    cp "$three/examples/jsm/loaders/GLTFLoader.js" "$viewer/vendor/three/examples/jsm/loaders/"
    cp "$three/examples/jsm/utils/BufferGeometryUtils.js" "$viewer/vendor/three/examples/jsm/utils/"
    cp "$three/examples/jsm/controls/OrbitControls.js" "$viewer/vendor/three/examples/jsm/controls/"
    cp web/package/index.js web/package/plimsoll.wasm "$viewer/vendor/plimsoll-runtime/"
  else
    echo "build-web: npm not installed: the viewer page is not assembled" >&2
  fi
fi
echo "== build-web: web/package/plimsoll.wasm, $(stat -c %s web/package/plimsoll.wasm) bytes ($(( $(date +%s) - start )) s)"
