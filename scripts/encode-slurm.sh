#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Submits the shards of an encode as a Slurm job array and their merge as a job that
# runs once every shard has succeeded (docs/format.md, "Shards"). The result is
# byte-identical to `svc encode DB -o OUT.svc`.
#
#   scripts/encode-slurm.sh [-y] [--wait] DB OUT.svc N [-- ENCODE_OPTIONS...]
#
# ENCODE_OPTIONS go to every `svc encode` (--quality, --i-spacing, --threads, ...; each
# array task asks Slurm for $SVC_SLURM_CPUS CPUs, default 1, and runs as many threads).
# DB, OUT's folder and svc ($SVC, default: svc on PATH) must be at the same paths on the
# compute nodes (a shared filesystem). $SBATCH_OPTIONS are added to both sbatch calls
# (--partition, --time, --account, ...). Parts and job logs go to OUT.svc.parts/; the
# parts are removed after the merge. A part already there is not encoded again: after a
# failed shard, run the same command again. With --wait the script returns when the
# merge has finished, with its status; a failed shard cancels the merge.
# Exit status: 0 submitted (or, with --wait, merged), 1 failed, 2 bad usage.
set -euo pipefail

usage() {
  sed -n '6p' "$0" | sed 's/^#  */usage: /' >&2
  exit 2
}

overwrite="" wait=()
while (($#)); do
  case "$1" in
    -y | --overwrite) overwrite=-y; shift ;;
    --wait) wait=(--wait); shift ;;
    -h | --help) sed -n '2,17p' "$0"; exit 0 ;;
    *) break ;;
  esac
done
(($# >= 3)) || usage
db=$1 out=$2 n=$3
shift 3
if (($#)); then [[ $1 == -- ]] || usage; shift; fi
[[ $n =~ ^[1-9][0-9]*$ ]] || { echo "encode-slurm: N must be a positive number, not '$n'" >&2; exit 2; }
cpus=${SVC_SLURM_CPUS:-1}
encode_opts=("$@")
[[ " ${encode_opts[*]} " == *" --threads "* ]] || encode_opts+=(--threads "$cpus")
svc=${SVC:-svc}
command -v sbatch >/dev/null || { echo "encode-slurm: sbatch is not installed (Debian: slurm-client)" >&2; exit 1; }
if [[ -e $out && -z $overwrite ]]; then
  echo "encode-slurm: $out exists; pass -y to replace it" >&2
  exit 1
fi

db=$(realpath "$db")
out=$(realpath -m "$out")
parts=$out.parts
mkdir -p "$parts"
q() { printf '%q' "$1"; }
part="$(q "$parts")/part-\${SLURM_ARRAY_TASK_ID}-of-$n.svcpart"
part_files=$(for k in $(seq 1 "$n"); do printf '%q ' "$parts/part-$k-of-$n.svcpart"; done)
# shellcheck disable=SC2086  # SBATCH_OPTIONS is a list of options
array=$(sbatch --parsable --job-name=svc-encode --array="1-$n" --cpus-per-task="$cpus" \
  --output="$parts/slurm-%A_%a.out" ${SBATCH_OPTIONS:-} \
  --wrap "test -e $part || $(q "$svc") encode $(q "$db") --shard \${SLURM_ARRAY_TASK_ID}/$n -o $part --quiet \
    $(printf '%q ' "${encode_opts[@]}")")
array=${array%%;*}
echo "encode-slurm: shards submitted as job array $array ($n tasks)"
# sbatch --wait returns 0 for a merge cancelled by a failed shard: the job leaves its
# own status.
status_file=$parts/merge.status
rm -f "$status_file"
# shellcheck disable=SC2086
sbatch --parsable --job-name=svc-merge --dependency="afterok:$array" --kill-on-invalid-dep=yes \
  --output="$parts/slurm-merge-%j.out" ${SBATCH_OPTIONS:-} "${wait[@]}" \
  --wrap "$(q "$svc") merge $part_files -o $(q "$out") $overwrite && rm -f $part_files; echo \$? >$(q "$status_file")" |
  sed 's/^\([0-9]*\).*/encode-slurm: merge submitted as job \1, after the array/'
status=${PIPESTATUS[0]}
if ((${#wait[@]})); then
  if ((status != 0)) || [[ $(cat "$status_file" 2>/dev/null) != 0 ]]; then
    echo "encode-slurm: the merge did not run or failed; logs in $parts" >&2
    exit 1
  fi
  echo "encode-slurm: wrote $out"
fi
exit "$status"
