#!/usr/bin/env bash
# Installs every Debian 12 package Plimsoll builds, tests and runs with. Idempotent: packages
# already present are left alone, and apt is not touched at all when nothing is missing.
# Runs apt-get as root, or through sudo when not root.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  # engine
  libeigen3-dev libassimp-dev nlohmann-json3-dev libstb-dev libopenexr-dev libcli11-dev
  # fast CPU path: vectorised sin, cos and exp of Gerstner waves (header-only)
  libxsimd-dev
  # bundle export: SHA-256 (OpenSSL's libcrypto)
  libssl-dev
  # runtime library (engine/runtime): inflates the bundle's PNG maps and EXR images; tinyexr's
  # header reads the EXR images, so a game links no OpenEXR
  zlib1g-dev libtinyexr-dev
  # OpenCL: ICD loader, C++ bindings, PoCL as the CPU device
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  # water-graph segmentation
  libcgal-dev
  # editor: window, GL entry points, headless EGL, ImGui, UI tests under Xvfb
  libglfw3-dev libepoxy-dev libegl-dev libgl-dev libimgui-dev libegl-mesa0 libgl1-mesa-dri xvfb xauth
  # tests
  googletest libgtest-dev
  # tests: OpenEXR's own tools (exrheader) read the exported EXR files back
  openexr
  # tests: key and mouse input sent to the editor window under Xvfb
  xdotool
  # fuzzing (scripts/fuzz.sh): clang with libFuzzer and the sanitizer runtimes
  clang libclang-rt-14-dev
  # the house style (scripts/check-format.sh)
  clang-format
  # builds: a build reuses the objects of the files unchanged since its last run (.ci/run)
  ccache
  # tests: xmllint checks plimsoll export --junit against a JUnit XML Schema
  libxml2-utils
  # Blender add-on tests (scripts/test-blender.sh): Blender's glTF importer needs numpy,
  # which --no-install-recommends leaves out
  blender python3-numpy
  # the Bullet adapter (engine/adapters/bullet) and its tests; built only where present
  libbullet-dev
  # radiation (engine/src/physics/radiation.cpp): Boost.Math's Bessel functions, header-only
  libboost-dev
  # the Python module (python/): pybind11 with NumPy arrays, its tests under pytest
  python3-dev python3-pybind11 python3-pytest
  # the runtime on the web (web/): emscripten builds the WebAssembly module, node runs the npm
  # package's tests, headless Chromium the three.js viewer's (npm: below)
  emscripten nodejs chromium
)

# The runtime's determinism across builds (scripts/test-determinism.sh): an aarch64 build run
# under qemu-user, with zlib for arm64 (Debian multiarch: the architecture is added to dpkg).
# Optional: where the arm64 archive cannot be reached, the rest installs and that comparison is
# skipped with a message.
cross_packages=(g++-aarch64-linux-gnu qemu-user zlib1g-dev:arm64)

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in "${packages[@]}"; do
  installed "$p" || missing+=("$p")
done
# npm comes with some nodejs builds (NodeSource's conflicts with Debian's npm package), so it is
# installed only where no npm is on the PATH.
command -v npm >/dev/null || missing+=(npm)
missing_cross=()
for p in "${cross_packages[@]}"; do
  installed "$p" || missing_cross+=("$p")
done

if [ ${#missing[@]} -eq 0 ] && [ ${#missing_cross[@]} -eq 0 ]; then
  echo "install-deps: all $(( ${#packages[@]} + ${#cross_packages[@]} )) packages present"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
if [ ${#missing_cross[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing_cross[*]} (optional)"
  if ! { "${sudo_cmd[@]}" dpkg --add-architecture arm64 &&
         "${sudo_cmd[@]}" apt-get update -qq &&
         "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing_cross[@]}"; }; then
    echo "install-deps: could not install ${missing_cross[*]}: the aarch64 determinism comparison will be skipped" >&2
    # An arm64 index that cannot be fetched would fail every later apt-get update.
    dpkg --print-foreign-architectures | grep -qx arm64 && ! installed zlib1g-dev:arm64 &&
      "${sudo_cmd[@]}" dpkg --remove-architecture arm64 || true
  fi
fi
