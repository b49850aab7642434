#!/usr/bin/env bash
# The whole test suite: makes sure the packages are there, builds, and runs ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --output-junit "$PWD/build/ctest-junit.xml"
# The full build's tests that must not skip: the window tests where Xvfb is installed, the
# Blender add-on where Blender is.
must=()
command -v Xvfb >/dev/null && must+=(--must-run '^EditorWindow\.' --must-run '^EditorPreviewWindow\.')
command -v blender >/dev/null && must+=(--must-run '^blender_addon$')
scripts/check-skips.py build/ctest-junit.xml "${must[@]}"
