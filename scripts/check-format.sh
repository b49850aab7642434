#!/usr/bin/env bash
# Checks that every C and C++ file of the repository follows .clang-format:
# `scripts/check-format.sh`. Exit 1 naming the files and showing the changes clang-format
# wants; `git ls-files '*.cpp' '*.h' '*.hpp' '*.c' | xargs clang-format -i` applies them.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null ||
  { echo "format: clang-format is not installed (scripts/install-deps.sh)" >&2; exit 1; }
mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.hpp' '*.c')
# One clang-format for all files: it names each line it would change as "FILE:LINE:COL: ".
mapfile -t bad < <(clang-format --dry-run "${files[@]}" 2>&1 |
  sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: .*code should be clang-formatted.*/\1/p' | sort -u)
if [ ${#bad[@]} -eq 0 ]; then
  echo "format: all ${#files[@]} C and C++ files follow .clang-format"; exit 0
fi
for f in "${bad[@]}"; do diff -u "$f" <(clang-format "$f") | head -40 || true; done
echo "format: ${#bad[@]} of ${#files[@]} files do not follow .clang-format: ${bad[*]}" >&2
exit 1
