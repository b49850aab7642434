#!/usr/bin/env bash
# Fresh Debian 12 machine to a first result: installs the missing packages, builds, and runs the
# main job on a bundled sample (validate, bake and mass properties of the navigation buoy).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
sample=assets/buoy.obj
echo
echo "== plimsoll validate $sample"
build/editor/plimsoll validate "$sample"
echo
echo "== plimsoll bake $sample --size 512 --out out/buoy_bake"
build/editor/plimsoll bake "$sample" --size 512 --out out/buoy_bake
echo
echo "== plimsoll massprops $sample --size 512 --density 600 --json   (texture-space)"
build/editor/plimsoll massprops "$sample" --size 512 --density 600 --json
echo
echo "== plimsoll massprops $sample --exact --density 600 --json       (exact reference)"
build/editor/plimsoll massprops "$sample" --exact --density 600 --json
