#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# scripts/encode-slurm.sh against a real one-node Slurm cluster on localhost
# (scripts/slurm-localhost.sh): the merged file equals the one-process encode; a failed
# shard cancels the merge, and the rerun encodes only that shard. Skipped (exit 77)
# where the cluster cannot start (no slurm-wlm/munge, not root).
# Usage: encode_slurm_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
bin=$1/bin
scripts=$2/scripts
test_name="encode-slurm test"
source "$2/tests/support/script_test.sh"
export SVC_SLURM_DIR=$work/slurm SVC_SLURM_PORT=${SVC_SLURM_PORT:-6837}
trap '"$scripts/slurm-localhost.sh" stop; rm -rf "$work"' EXIT

if ! started=$("$scripts/slurm-localhost.sh" start 2>"$work/start.log"); then
  echo "SKIPPED: the one-node Slurm cluster did not start:"
  cat "$work/start.log"
  exit 77
fi
eval "$started"
export SVC=$bin/svc

"$bin/svc-scene" "$work/db" --grid 7,1,4 --face-size 16 --quiet
"$SVC" encode "$work/db" -o "$work/one.svc" --quiet
timeout 300 "$scripts/encode-slurm.sh" --wait "$work/db" "$work/slurm.svc" 3
cmp "$work/one.svc" "$work/slurm.svc" || fail "3 shards on Slurm differ from the one-process encode"

# Shard 2 fails while $work/broken exists: the merge is cancelled, nothing is written.
write_flaky_svc "$bin/svc"
touch "$work/broken"
if SVC=$work/flaky-svc timeout 300 "$scripts/encode-slurm.sh" --wait "$work/db" "$work/retry.svc" 3; then
  fail "a failed shard did not fail the run"
fi
[[ ! -e $work/retry.svc ]] || fail "the merge ran after a failed shard"
rm "$work/broken" "$work/runs.log"
SVC=$work/flaky-svc timeout 300 "$scripts/encode-slurm.sh" --wait "$work/db" "$work/retry.svc" 3
cmp "$work/one.svc" "$work/retry.svc" || fail "the rerun's merged file differs"
[[ $(grep -c -- "--shard" "$work/runs.log") == 1 ]] || fail "the rerun encoded more than the failed shard"
echo "encode-slurm: 3 shards as a Slurm job array give the one-process bytes"
