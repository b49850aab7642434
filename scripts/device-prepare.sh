#!/usr/bin/env bash
# Builds what scripts/device-bench.sh runs on a lent GPU machine (docs/design.md, "Measuring on
# a GPU"): the CLI with OpenCL and without CGAL or the editor's window, in build-device/, plus
# the shared libraries it needs that such a machine lacks, in build-device/devlibs/. Both are
# ignored by git, so a device call names them in `carry`:
#   carry: ["build-device/editor/plimsoll", "build-device/devlibs", "build-device/spot.obj"]
#   (and "build-device/before" where BEFORE= built one)
# The device's own C and C++ runtimes are newer than Debian 12's and are used as they are; so
# is its OpenCL loader when it has one (ours is carried for when it does not).
# BEFORE=<git revision> also builds that revision's CLI, the same way, as
# build-device/before/plimsoll: device-bench.sh then runs it beside this one in the same call
# (carry "build-device/before" too). Its libraries must be among this build's. It stays until
# the next BEFORE= (delete build-device/before to run this build alone).
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
configureAndBuild() {  # source folder, build folder
  cmake -S "$1" -B "$2" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPLIMSOLL_WITH_OPENCL=ON \
    -DPLIMSOLL_WITH_CGAL=OFF -DPLIMSOLL_BUILD_EDITOR_GUI=OFF "${launcher[@]}" >/dev/null
  cmake --build "$2" --parallel "$(nproc)" --target plimsoll
}
configureAndBuild . build-device
if [ -n "${BEFORE:-}" ]; then
  rm -rf build-device/before
  tree=$(mktemp -d)/plimsoll-before
  git worktree add --detach "$tree" "$BEFORE" >/dev/null
  configureAndBuild "$tree" "$tree/build-device"
  mkdir -p build-device/before
  cp "$tree/build-device/editor/plimsoll" build-device/before/plimsoll
  git rev-parse "$BEFORE" >build-device/before/revision
  git worktree remove --force "$tree"
fi
rm -rf build-device/devlibs
mkdir -p build-device/devlibs/opencl
# Everything ldd resolves except the C and C++ runtimes and the loader.
ldd build-device/editor/plimsoll | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' |
  while read -r name path; do
    case "$name" in
      libc.so.*|libm.so.*|libstdc++.so.*|libgcc_s.so.*|ld-linux*|libpthread.so.*|libdl.so.*|librt.so.*) ;;
      libOpenCL.so.*) cp -L "$path" build-device/devlibs/opencl/ ;;
      *) cp -L "$path" build-device/devlibs/ ;;
    esac
  done
# The shared folder does not travel: a copy of its cow, for the bench's second mesh.
[ -f ../shared/meshes/spot.obj ] && cp ../shared/meshes/spot.obj build-device/spot.obj
du -sh build-device/editor/plimsoll build-device/devlibs build-device/before 2>/dev/null || true
