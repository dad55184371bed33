#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Runs the README's tool commands (the block after "<!-- readme-commands") exactly as
# written, in an empty folder where build/ is the build tree, and checks what they left:
# a database, an .svc file that grew by the added cells, a decoded face, an inspect sheet.
set -euo pipefail
build_dir=$1
source_dir=$2
test_name="readme commands test"
source "$source_dir/tests/support/script_test.sh"

commands=$(awk '/<!-- readme-commands/ {found = 1; next}
                found && /^```sh/ {inside = 1; next}
                inside && /^```/ {exit}
                inside {print}' "$source_dir/README.md")
[[ -n "$commands" ]] || fail "no readme-commands block found in README.md"
ln -s "$build_dir" "$work/build"
if ! (cd "$work" && bash -e -u -o pipefail -c "$commands") >"$work/commands.log" 2>&1; then
  cat "$work/commands.log" >&2
  fail "the README's commands failed"
fi

cd "$work"
[[ -f scene/manifest.json && -f scene.svc && -f mb.png ]] || fail "scene, scene.svc or mb.png missing"
[[ -f decoded/cells/4_0_4/px.png ]] || fail "the decoded face is missing"
grep -q "PSNR-Y" commands.log || fail "encode --psnr printed no PSNR"
cells=$(build/bin/svc info --json scene.svc | grep -c '"face_bytes"')
[[ $cells -eq 35 ]] || fail "after svc add the file holds $cells cells, not 35 (5x1x7)"
build/bin/svc verify --quiet scene.svc || fail "the extended file does not verify"
build/bin/svc verify --quiet fast.svc || fail "the --speed 1 file does not verify"
build/bin/svc encode --quiet scene/ -o whole.svc || fail "the one-process encode for the shard check failed"
cmp -s sharded.svc whole.svc || fail "the merged parts differ from the one-process encode"
