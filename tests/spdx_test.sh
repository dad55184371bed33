#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Every source file of the tree names its license (SPDX) in its first lines: C and C++
# sources, scripts, CMake files.
# Usage: spdx_test.sh SOURCE_DIR
set -euo pipefail
cd "$1"
missing=0
while IFS= read -r file; do
  if ! head -n 3 "$file" | grep -q 'SPDX-License-Identifier: BSD-2-Clause'; then
    echo "spdx: $file names no license in its first lines" >&2
    missing=$((missing + 1))
  fi
done < <(git ls-files '*.cc' '*.h' '*.c' '*.sh' '*.py' '*.cmake' '*CMakeLists.txt' 2>/dev/null || find . -name '*.cc')
((missing == 0)) || exit 1
echo "spdx: every source file names its license"
