#!/usr/bin/env bash
# The runtime's determinism across builds (docs/c-abi.md, "Determinism"): every sample
# project's body is exported once and replayed by the float_body example (`--csv`: the rows of
# `plimsoll simulate --out` and the final state's hash) as built by g++ (its AVX2 build and its
# baseline build, PLIMSOLL_ISA=baseline), by clang, and by g++ for aarch64 run under qemu-user.
# Every output must equal the native g++ one byte for byte. The aarch64 part needs Debian's
# g++-aarch64-linux-gnu, qemu-user and zlib1g-dev:arm64 (scripts/install-deps.sh); without
# them it is skipped with a message, and the script exits 77 only if nothing but the native
# build could run. Usage: scripts/test-determinism.sh [PLIMSOLL_EXECUTABLE] [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
plimsoll=${1:-build/editor/plimsoll}
seconds=${2:-10}
[[ -x "$plimsoll" ]] || { echo "test-determinism: $plimsoll not found (build the project first)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# shellcheck source=scripts/standalone-cmake.sh
source scripts/standalone-cmake.sh
start=$(date +%s)

# One build of the runtime and float_body per compiler: $1 name, the rest CMake arguments.
build() {
  local name=$1
  shift
  echo "== build: $name"
  cmake -S engine/runtime -B "$work/$name" "${generator[@]}" "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release "$@" \
    >"$work/$name.log" 2>&1 || { cat "$work/$name.log"; exit 1; }
  cmake --build "$work/$name" --parallel 2 --target plimsoll_float_body >>"$work/$name.log" 2>&1 \
    || { tail -40 "$work/$name.log"; exit 1; }
}

runs=("gcc" "gcc-baseline")
build gcc -DCMAKE_C_COMPILER=gcc -DCMAKE_CXX_COMPILER=g++
if command -v clang++ >/dev/null 2>&1; then
  build clang -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++
  runs+=("clang")
else
  echo "test-determinism: clang++ not installed: the clang build is not compared"
fi
if command -v aarch64-linux-gnu-g++ >/dev/null 2>&1 && command -v qemu-aarch64 >/dev/null 2>&1 &&
   [[ -f /usr/lib/aarch64-linux-gnu/libz.a ]]; then
  build aarch64 -DCMAKE_SYSTEM_NAME=Linux -DCMAKE_SYSTEM_PROCESSOR=aarch64 \
    -DCMAKE_C_COMPILER=aarch64-linux-gnu-gcc -DCMAKE_CXX_COMPILER=aarch64-linux-gnu-g++ \
    -DZLIB_LIBRARY=/usr/lib/aarch64-linux-gnu/libz.a -DZLIB_INCLUDE_DIR=/usr/include \
    -DCMAKE_EXE_LINKER_FLAGS=-static
  runs+=("aarch64")
else
  echo "test-determinism: g++-aarch64-linux-gnu, qemu-user or zlib1g-dev:arm64 missing: aarch64 is not compared"
fi

echo "== export the sample projects"
for project in projects/*.plim.json; do
  "$plimsoll" export "$project" --out "$work/bundles" --quiet >/dev/null
done

failures=0
compared=0
while IFS= read -r manifest; do
  bundle=$(dirname "$manifest")
  label=${bundle#"$work/bundles/"}
  differing=0
  for run in "${runs[@]}"; do
    case $run in
      gcc) cmd=("$work/gcc/plimsoll_float_body") ;;
      gcc-baseline) cmd=(env PLIMSOLL_ISA=baseline "$work/gcc/plimsoll_float_body") ;;
      clang) cmd=("$work/clang/plimsoll_float_body") ;;
      aarch64) cmd=(qemu-aarch64 "$work/aarch64/plimsoll_float_body") ;;
    esac
    if ! "${cmd[@]}" "$bundle" "$seconds" --csv "$work/$run.csv" >"$work/$run.txt" 2>"$work/$run.err"; then
      if grep -q "radiates\|integrator" "$work/$run.err"; then
        echo "  $label: not replayed ($(cat "$work/$run.err"))"
        continue 2
      fi
      echo "test-determinism: $label, $run: float_body failed:" >&2
      cat "$work/$run.err" >&2
      exit 1
    fi
    cat "$work/$run.txt" >>"$work/$run.csv"
    if [[ $run != gcc ]] && ! cmp -s "$work/gcc.csv" "$work/$run.csv"; then
      echo "  $label: $run DIFFERS from gcc: $(diff "$work/gcc.csv" "$work/$run.csv" | head -3 | tr '\n' ' ')"
      failures=$((failures + 1))
      differing=1
    fi
  done
  [[ $differing -eq 1 ]] || echo "  $label: $(tail -n 1 "$work/gcc.csv"), the same from ${runs[*]}"
  compared=$((compared + 1))
done < <(find "$work/bundles" -name manifest.json | sort)

echo "== $compared bodies, builds: ${runs[*]}; $failures differences ($(( $(date +%s) - start )) s)"
[[ $compared -gt 0 ]] || { echo "test-determinism: no body was compared" >&2; exit 1; }
[[ $failures -eq 0 ]] || exit 1
[[ ${#runs[@]} -gt 2 ]] || exit 77
