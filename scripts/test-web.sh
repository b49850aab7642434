#!/usr/bin/env bash
# The runtime on the web (web/README.md): builds the WebAssembly module and its native
# counterpart (scripts/build-web.sh), runs the npm package's tests (forces on a few hundred poses
# and float_body --csv's rows and state hashes, against the native runtime built from the same
# sources), then exports projects/buoy.plim.json with `plimsoll export --web`, opens the viewer in
# headless Chromium, replays 10 simulated seconds in its deterministic fixed-step mode and checks
# that its state hash is the native float_body's for the same steps; then the interactive page on
# the damaged boat: a body dropped, the first pushed by a click. Prints the screenshots' paths.
# Exits 77 where emscripten, node, npm or Chromium is missing.
# Usage: scripts/test-web.sh [PLIMSOLL_EXECUTABLE] [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
plimsoll=$(realpath -m "${1:-build/editor/plimsoll}")
seconds=${2:-10}
chromium=${CHROMIUM:-$(command -v chromium || command -v chromium-browser || true)}
for tool in emcmake node npm; do
  command -v "$tool" >/dev/null 2>&1 || { echo "test-web: $tool not installed (scripts/install-deps.sh): skipped" >&2; exit 77; }
done
[[ -n "$chromium" && -x "$chromium" ]] || { echo "test-web: Chromium not installed (scripts/install-deps.sh): skipped" >&2; exit 77; }
[[ -x "$plimsoll" ]] || { echo "test-web: $plimsoll not found (build the project first)" >&2; exit 1; }
start=$(date +%s)
scripts/build-web.sh

echo "== npm test (web/package)"
(cd web/package && PLIMSOLL_CLI="$plimsoll" npm test --silent)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "== npm pack (web/package): the tarball, unpacked elsewhere, loads its module"
(cd web/package && npm pack --silent --pack-destination "$work" >/dev/null)
mkdir -p "$work/unpacked" && tar -xzf "$work"/plimsoll-runtime-*.tgz -C "$work/unpacked"
(cd "$work/unpacked/package" && node --input-type=module -e \
  'import { loadRuntime } from "./index.js"; const r = await loadRuntime(); console.log(`the packed module: runtime ${r.version}`);')

echo "== the viewer in headless Chromium: $seconds s of projects/buoy.plim.json"
shots=$(mktemp -d "${TMPDIR:-/tmp}/plimsoll-web-XXXXXX")
"$plimsoll" export projects/buoy.plim.json --out "$work/site" --web --quiet >/dev/null
bundle=$work/site/$(node -e 'console.log(JSON.parse(require("fs").readFileSync(process.argv[1])).bundles[0])' "$work/site/bundles.json")
result=$(node web/viewer/test/browser-run.mjs "$work/site" "$seconds" "$shots/viewer.png" "$chromium")
echo "browser: $result"
web_hash=$(node -e 'console.log(JSON.parse(process.argv[1]).stateHash)' "$result")
native_hash=$(build-web/native/runtime/plimsoll_float_body "$bundle" "$seconds" --csv "$work/native.csv" | sed -n 's/^state hash //p')
echo "screenshot: $shots/viewer.png"
if [[ "$web_hash" != "$native_hash" ]]; then
  echo "test-web: the viewer's state hash $web_hash differs from native float_body's $native_hash" >&2
  exit 1
fi
echo "state hash $web_hash: the viewer's and native float_body's (the same sources and math) after $seconds s"

echo "== the interactive viewer: projects/damaged_boat.plim.json, a body dropped, the first pushed"
"$plimsoll" export projects/damaged_boat.plim.json --out "$work/boat" --web --quiet >/dev/null
result=$(node web/viewer/test/browser-run.mjs "$work/boat" 3 "$shots/interactive.png" "$chromium" --interactive)
echo "browser: $result"
node -e '
  const r = JSON.parse(process.argv[1]);
  const problems = [];
  if (r.bodies.length !== 2) problems.push(`${r.bodies.length} bodies after one was dropped`);
  if (!(r.pushedSpeed > 0.3)) problems.push(`the pushed body moves at ${r.pushedSpeed} m/s across the water`);
  if (!r.bodies.every((b) => [...b.position, ...b.velocity, b.water].every(Number.isFinite))) problems.push("a state is not finite");
  if (problems.length) { console.error(`test-web: the interactive viewer: ${problems.join("; ")}`); process.exit(1); }
' "$result"
echo "screenshot: $shots/interactive.png"
# The project's own build of the runtime (the CLI's build folder, default options) gives the same
# bits: the portable sin, cos and exp are its default too (docs/c-abi.md, "Determinism").
default=$(dirname "$plimsoll")/../engine/runtime/plimsoll_float_body
if [[ -x "$default" ]]; then
  default_hash=$("$default" "$bundle" "$seconds" --csv "$work/default.csv" | sed -n 's/^state hash //p')
  [[ "$default_hash" == "$web_hash" ]] || {
    echo "test-web: the project build's float_body gives state hash $default_hash, the viewer $web_hash" >&2
    exit 1
  }
  echo "the project build's float_body: state hash $default_hash, the same"
fi
echo "== test-web: ok ($(( $(date +%s) - start )) s)"
