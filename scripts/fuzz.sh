#!/usr/bin/env bash
# Fuzzes the loaders: builds the libFuzzer targets of fuzz/ with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer in build-fuzz/ (engine + targets only), runs each one for a bounded
# time on a copy of its seed corpus (fuzz/corpus/<target>/, never modified; a mesh format's also
# on the shared real assets of that format when ../shared/real-assets is there), and fails on any
# crash, leak, undefined behaviour, input slower than 30 s or allocation over 2 GB.
#   scripts/fuzz.sh [seconds-per-target] [target ...]     (default: 30 s, every target)
# A finding is left in build-fuzz/findings/<target>-crash-<sha1> (add it to the corpus once
# fixed): reproduce it with build-fuzz/fuzz/fuzz_<target> build-fuzz/findings/<file>.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-30}"
[ $# -gt 0 ] && shift
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(project graph manifest mesh_obj validate repair mesh_ply mesh_stl
                                      mesh_gltf mesh_glb mesh_fbx runtime_bundle runtime_png)

scripts/install-deps.sh
start=$(date +%s)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ \
      -DPLIMSOLL_FUZZ=ON "${launcher[@]}" >/dev/null
cmake --build build-fuzz --target fuzz_all --parallel "$(nproc)"
built=$(date +%s)
echo "fuzz: build took $((built - start)) s"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p build-fuzz/findings
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0"
# Each libFuzzer run is one process on one core: the targets run $(nproc) at a time, each for
# the same bounded time, and their reports are printed in order once all have finished.
fuzz_one() {
  local t=$1 log="$work/$1.log" t0 result runs corpus
  local dict=()
  cp -r "fuzz/corpus/$t" "$work/$t"
  # A mesh format's target also starts from the shared real assets of that format, where the
  # checkout has them beside it (../shared/real-assets; never copied into fuzz/corpus).
  if [[ $t == mesh_* && -d ../shared/real-assets ]]; then
    find ../shared/real-assets -type f -iname "*.${t#mesh_}" -size -512k \
         -exec cp {} "$work/$t/" \;
  fi
  [ -f "fuzz/$t.dict" ] && dict=("-dict=fuzz/$t.dict")
  t0=$(date +%s)
  if "build-fuzz/fuzz/fuzz_$t" "$work/$t" "${dict[@]}" -max_total_time="$seconds" \
       -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=30 -print_final_stats=1 \
       -artifact_prefix="build-fuzz/findings/$t-" >"$log" 2>&1; then
    result=ok
  else
    result=FAILED
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  corpus=$(find "$work/$t" -type f | wc -l)
  {
    printf 'fuzz: %-14s %-6s %10s executions in %4d s, corpus %d inputs\n' "$t" "$result" \
           "${runs:-?}" "$(( $(date +%s) - t0 ))" "$corpus"
    if [ "$result" = FAILED ]; then
      grep -E "ERROR|runtime error|SUMMARY|Test unit written|deadly signal" "$log" | head -20 || true
      tail -60 "$log"
    fi
  } >"$work/$t.report"
  [ "$result" = ok ]
}
jobs_at_once=$(nproc)
running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$jobs_at_once" ]; then
    wait -n || true
    running=$((running - 1))
  fi
  fuzz_one "$t" &
  running=$((running + 1))
done
wait || true
failed=()
for t in "${targets[@]}"; do
  cat "$work/$t.report"
  grep -q "^fuzz: $t *ok " "$work/$t.report" || failed+=("$t")
done
echo "fuzz: total $(( $(date +%s) - start )) s (build $((built - start)) s)"
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]} (inputs in build-fuzz/findings/)" >&2
  exit 1
fi
