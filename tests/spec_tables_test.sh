#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# docs/codec.md's normative tables equal the constants in codec/ (scripts/spec-tables.py),
# and the check fails when either side drifts: a number changed in the document, a
# number changed in the source, a table missing from the document.
set -euo pipefail
root=$1
script="$root/scripts/spec-tables.py"
python3 "$script" --doc "$root/docs/codec.md" --source "$root/codec"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The document drifts: one trained probability changed.
sed '/<!-- spec-table: kBFrameTable -->/,/<!-- \/spec-table -->/ s/^\(   0: *\)\([0-9]*\)/\1\21/' \
  "$root/docs/codec.md" >"$work/doc.md"
cmp -s "$root/docs/codec.md" "$work/doc.md" && { echo "the planted change did not apply"; exit 1; }
if python3 "$script" --doc "$work/doc.md" --source "$root/codec" >/dev/null 2>&1; then
  echo "a changed table in the document passed"; exit 1
fi

# The source drifts: one interpolation tap changed.
cp -r "$root/codec" "$work/codec"
file=$(grep -rl "kSmoothLumaTaps = " "$work/codec")
sed -i 's/{0, 0, 10, 30, 21, 3, 0, 0}/{0, 0, 11, 29, 21, 3, 0, 0}/' "$file"
grep -q "11, 29, 21" "$file" || { echo "the planted source change did not apply"; exit 1; }
if python3 "$script" --doc "$root/docs/codec.md" --source "$work/codec" >/dev/null 2>&1; then
  echo "a changed table in the source passed"; exit 1
fi

# A table missing from the document.
sed '/<!-- spec-table: kAngle -->/d' "$root/docs/codec.md" >"$work/doc.md"
if python3 "$script" --doc "$work/doc.md" --source "$root/codec" >/dev/null 2>&1; then
  echo "a document without the angle table passed"; exit 1
fi
echo "spec tables: check passes on the tree and fails on each planted drift"
