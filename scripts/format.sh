#!/usr/bin/env bash
# Formats every C++ source of the repository with the repository's .clang-format
# (clang-format 14, Debian 12's `clang-format` package).
#   scripts/format.sh          rewrite the files in place
#   scripts/format.sh --check  change nothing; list the files that differ and exit 1 if any do
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "format.sh: clang-format is not installed (scripts/install-deps.sh)" >&2; exit 2; }
mapfile -t files < <(git ls-files '*.cpp' '*.h')
if [ "${1:-}" = "--check" ]; then
  # One clang-format per batch of files, on every core; only when a batch differs are its files
  # checked one by one to name them.
  if printf '%s\0' "${files[@]}" |
    xargs -0 -P"$(nproc)" -n 50 clang-format --dry-run -Werror >/dev/null 2>&1; then
    exit 0
  fi
  bad=0
  for f in "${files[@]}"; do
    if ! clang-format --dry-run -Werror "$f" >/dev/null 2>&1; then
      echo "not formatted: $f"
      bad=1
    fi
  done
  exit $bad
fi
clang-format -i "${files[@]}"
