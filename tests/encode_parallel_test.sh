#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# scripts/encode-parallel.sh on local cores: the merged file equals the one-process
# encode; an existing output is kept; a failed shard leaves no output and its rerun
# encodes only the missing part.
# Usage: encode_parallel_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
bin=$1/bin
script=$2/scripts/encode-parallel.sh
test_name="encode-parallel test"
source "$2/tests/support/script_test.sh"
export SVC=$bin/svc

"$bin/svc-scene" "$work/db" --grid 7,1,4 --face-size 16 --quiet
"$SVC" encode "$work/db" -o "$work/one.svc" --quiet --threads 2

"$script" "$work/db" "$work/par.svc" 3 -- --quality 75 >/dev/null
cmp "$work/one.svc" "$work/par.svc" || fail "3 shards on GNU parallel differ from the one-process encode"
[[ ! -e $work/par.svc.parts ]] || fail "the parts folder was left behind"

echo keep >"$work/kept.svc"
if "$script" "$work/db" "$work/kept.svc" 2 2>/dev/null; then fail "an existing output was replaced without -y"; fi
[[ $(cat "$work/kept.svc") == keep ]] || fail "an existing output was changed"
"$script" -y "$work/db" "$work/kept.svc" 2 >/dev/null
cmp "$work/one.svc" "$work/kept.svc" || fail "-y did not write the merged file"

# Shard 2 of 3 fails while $work/broken exists: nothing is merged, and the rerun encodes
# shard 2 alone.
write_flaky_svc "$bin/svc"
touch "$work/broken"
if SVC=$work/flaky-svc "$script" "$work/db" "$work/retry.svc" 3 -- --threads 1 2>/dev/null; then
  fail "a failed shard was not reported"
fi
[[ ! -e $work/retry.svc ]] || fail "a failed run wrote the output"
# Parts that were complete when parallel stopped are kept and not encoded again.
for k in 1 3; do
  if [[ -e $work/retry.svc.parts/part-$k-of-3.svcpart ]]; then echo "$k" >>"$work/done-before"; fi
done
[[ ! -e $work/retry.svc.parts/part-2-of-3.svcpart ]] || fail "the failed shard left a part"
rm "$work/broken" "$work/runs.log"
SVC=$work/flaky-svc "$script" "$work/db" "$work/retry.svc" 3 >/dev/null
cmp "$work/one.svc" "$work/retry.svc" || fail "the rerun's merged file differs"
grep -q -- "--shard 2/3" "$work/runs.log" || fail "the rerun did not encode shard 2"
while read -r k; do
  if grep -q -- "--shard $k/3" "$work/runs.log"; then fail "the rerun encoded part $k again"; fi
done < <(cat "$work/done-before" 2>/dev/null)
echo "encode-parallel: 3 shards on local cores give the one-process bytes"
