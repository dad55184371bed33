#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Checks that the tracked C++ files (or the files named) are formatted as .clang-format
# says, with clang-format 14 (Debian 12: clang-format-14). Lists each file that differs
# and exits 1; --fix rewrites them in place instead.
# Usage: scripts/check-format.sh [--fix] [FILE...]
set -euo pipefail
cd "$(dirname "$0")/.."
fix=0
if [[ "${1:-}" == --fix ]]; then
  fix=1
  shift
fi
clang_format=${CLANG_FORMAT:-clang-format-14}
if ! command -v "$clang_format" >/dev/null; then
  echo "check-format: $clang_format not found (apt-get install clang-format-14, or set CLANG_FORMAT)" >&2
  exit 2
fi
if (($# > 0)); then
  files=("$@")
else
  mapfile -t files < <(git ls-files '*.h' '*.cc' '*.cpp')
fi

unformatted=0
for file in "${files[@]}"; do
  if ((fix)); then
    "$clang_format" --style=file -i "$file"
  elif ! "$clang_format" --style=file "$file" | cmp -s "$file" -; then
    echo "$file"
    unformatted=$((unformatted + 1))
  fi
done
if ((unformatted > 0)); then
  echo "check-format: $unformatted of ${#files[@]} files differ from .clang-format (scripts/check-format.sh --fix)" >&2
  exit 1
fi
echo "check-format: ${#files[@]} files formatted"
