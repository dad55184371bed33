#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Encodes an svc-input database in N shards run by GNU parallel, on this machine's cores
# or on other machines, then merges the parts (docs/format.md, "Shards"). The result is
# byte-identical to `svc encode DB -o OUT.svc`.
#
#   scripts/encode-parallel.sh [-y] [--sshloginfile FILE] DB OUT.svc [N] [-- ENCODE_OPTIONS...]
#
# N defaults to the number of cores. ENCODE_OPTIONS go to every `svc encode` (--quality,
# --i-spacing, ...; each shard runs with --threads 1 unless they say otherwise). With
# --sshloginfile, parallel runs the shards on the machines it lists: svc must be on their
# PATH and DB and OUT's folder must be at the same paths there (a shared filesystem).
# Parts are written to OUT.svc.parts/ and removed after the merge; a part already there
# is complete (parts appear only when complete) and is not encoded again, so after a
# failed or killed shard, running the same command again encodes only what is missing.
# $SVC names the svc program (default: svc on PATH). Exit status: 0 done, 1 an encode or
# the merge failed, 2 bad usage.
set -euo pipefail

usage() {
  sed -n '6p' "$0" | sed 's/^#  */usage: /' >&2
  exit 2
}

overwrite=()
parallel_opts=()
while (($#)); do
  case "$1" in
    -y | --overwrite) overwrite=(-y); shift ;;
    --sshloginfile) (($# >= 2)) || usage; parallel_opts+=(--sshloginfile "$2"); shift 2 ;;
    -h | --help) sed -n '2,18p' "$0"; exit 0 ;;
    *) break ;;
  esac
done
(($# >= 2)) || usage
db=$1 out=$2
shift 2
n=$(nproc)
if (($#)) && [[ $1 != -- ]]; then n=$1; shift; fi
if (($#)); then [[ $1 == -- ]] || usage; shift; fi
encode_opts=("$@")
[[ $n =~ ^[1-9][0-9]*$ ]] || { echo "encode-parallel: N must be a positive number, not '$n'" >&2; exit 2; }
[[ " ${encode_opts[*]} " == *" --threads "* ]] || encode_opts+=(--threads 1)
svc=${SVC:-svc}
command -v parallel >/dev/null || { echo "encode-parallel: GNU parallel is not installed (Debian: parallel)" >&2; exit 1; }
if [[ -e $out && ${#overwrite[@]} == 0 ]]; then
  echo "encode-parallel: $out exists; pass -y to replace it" >&2
  exit 1
fi

db=$(realpath "$db")
parts=$(realpath -m "$out.parts")
mkdir -p "$parts"
# Remote shells see the same absolute paths; each shard skips a part already there.
part="$(printf '%q' "$parts")/part-{}-of-$n.svcpart"
parallel --will-cite --halt now,fail=1 --jobs "${SVC_PARALLEL_JOBS:-100%}" "${parallel_opts[@]}" \
  "test -e $part || $(printf '%q' "$svc") encode $(printf '%q' "$db") --shard {}/$n -o $part --quiet \
   $(printf '%q ' "${encode_opts[@]}")" ::: $(seq 1 "$n")
mapfile -t part_files < <(seq 1 "$n" | sed "s|.*|$parts/part-&-of-$n.svcpart|")
"$svc" merge "${part_files[@]}" -o "$out" "${overwrite[@]}"
rm -rf "$parts"
