#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Fails when a stream named in the manifest is on disk but not committed: the suite would
# pass here and find nothing in a fresh clone. Skipped (77) outside a git checkout.
# Usage: check_committed.sh SOURCE_ROOT
set -euo pipefail
root=$1
if ! git -C "$root" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  echo "not a git checkout: nothing to check"
  exit 77
fi
missing=0
while read -r name _; do
  [[ -z $name || $name == \#* ]] && continue
  path=tests/conformance/streams/$name.svc
  if ! git -C "$root" ls-files --error-unmatch -- "$path" >/dev/null 2>&1; then
    echo "not committed: $path"
    missing=$((missing + 1))
  fi
done <"$root/tests/conformance/streams.txt"
if ((missing > 0)); then
  echo "$missing stream(s) of tests/conformance/streams.txt are not in git (check .gitignore)"
  exit 1
fi
echo "every stream of tests/conformance/streams.txt is committed"
