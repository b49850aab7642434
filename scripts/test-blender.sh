#!/usr/bin/env bash
# The Blender add-on (blender/plimsoll_blender/) in Blender itself, headless: exports three
# sample projects' bundles with plimsoll (a water graph and a painted map; a painted shell;
# a plain solid), imports them through the add-on
# (blender/tests/test_import_bundle.py), then exports meshes as projects, validates them and
# round-trips them through plimsoll's export (blender/tests/test_export_project.py); then,
# where the plimsoll Python module is built ($PLIMSOLL_PYTHON_PATH, else build/python beside
# the executable's build/editor), floats the sample buoy on waves as keyframes through the
# module and checks them against the module's own simulate (blender/tests/test_float.py).
#   scripts/test-blender.sh PLIMSOLL_EXECUTABLE
# Exits 77 (ctest's SKIP_RETURN_CODE for test blender_addon) when blender is not installed.
set -euo pipefail
plimsoll=$1
if ! command -v blender >/dev/null; then
  echo "test-blender: blender is not installed (scripts/install-deps.sh installs it): skipped"
  exit 77
fi
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$plimsoll" export "$root/projects/damaged_boat.plim.json" "$root/projects/buoy.plim.json" \
  "$root/projects/box_half_draft.plim.json" --out "$work/bundles" --jobs 2 --quiet >/dev/null
bundles=("$work/bundles/damaged_boat/boat" "$work/bundles/buoy/buoy" "$work/bundles/box_half_draft/box")
# --python-exit-code: an uncaught Python error fails the run (Blender exits 0 otherwise).
run_blender() {
  blender -b --factory-startup --python-exit-code 1 --python "$@"
}
run_blender "$root/blender/tests/test_import_bundle.py" -- "${bundles[@]}"
PLIMSOLL="$plimsoll" run_blender "$root/blender/tests/test_export_project.py" -- "$work/projects" "${bundles[@]}"
module_dir=${PLIMSOLL_PYTHON_PATH:-$(cd "$(dirname "$plimsoll")/.." && pwd)/python}
if compgen -G "$module_dir/plimsoll*.so" >/dev/null; then
  PLIMSOLL_PYTHON_PATH="$module_dir" run_blender "$root/blender/tests/test_float.py" -- \
    "$root/assets/buoy.obj" "$work/float"
else
  echo "test-blender: the float test skipped: no plimsoll Python module in $module_dir"
fi
echo "test-blender: passed"
