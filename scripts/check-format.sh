#!/usr/bin/env bash
# Checks that the lines changed against a base (default origin/main, else main) follow
# .clang-format: `scripts/check-format.sh [BASE]`. Only changed lines are looked at, so that
# the tree is never reformatted as a whole. Exit 1 with the diff clang-format wants.
set -euo pipefail
cd "$(dirname "$0")/.."
base=${1:-$(git rev-parse --verify -q origin/main >/dev/null && echo origin/main || echo main)}
out=$(git clang-format --diff "$base" -- '*.cpp' '*.h' '*.hpp' '*.c' 2>&1 || true)
case "$out" in
  ""|*"no modified files to format"*|*"did not modify any files"*)
    echo "format: changed lines against $base follow .clang-format"; exit 0 ;;
esac
echo "$out"
echo "format: the lines above, changed against $base, do not follow .clang-format" >&2
exit 1
