#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Sharded encoding on this machine: the speed-up of N shards run by GNU parallel (one
# thread each, scripts/encode-parallel.sh) over one process using every core and over
# one single-threaded process, each merged file checked against the one-process bytes;
# then the peak memory of the 100,000-face encode (build/bin/svc_memory_tests).
#
#   bench/shard-speedup.sh [BUILD_DIR] [N...]     (default: build, 2 and the core count)
#
# The database: `svc-scene --grid 9,1,9 --face-size 256` (the hall, 486 faces). Each
# process starts in about a second (library start-up), which a larger database amortizes.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath "${1:-$root/build}")
shift || true
cores=$(nproc)
shard_counts=("$@")
((${#shard_counts[@]})) || mapfile -t shard_counts < <(printf '%s\n' 2 "$cores" | sort -nu)
export SVC=$build/bin/svc
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Runs a command; prints "WALL CPU" in seconds (CPU: user + system of it and its children).
seconds() {
  local TIMEFORMAT='%R %U %S' times
  times=$({ time "$@" >/dev/null 2>&1; } 2>&1) || { echo "shard-speedup: $* failed" >&2; exit 1; }
  awk '{ printf "%.2f %.2f\n", $1, $2 + $3 }' <<<"$times"
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }

"$build/bin/svc-scene" "$work/db" --grid 9,1,9 --face-size 256 --quiet
echo "machine: $cores cores; database: svc-scene --grid 9,1,9 --face-size 256 (486 faces)"
read -r single single_cpu < <(seconds "$SVC" encode "$work/db" -o "$work/single.svc" --threads 1 --quiet)
read -r whole whole_cpu < <(seconds "$SVC" encode "$work/db" -o "$work/one.svc" --threads "$cores" --quiet)
cmp "$work/single.svc" "$work/one.svc"
printf "one process, 1 thread:      %7.2f s (CPU %.2f s)\n" "$single" "$single_cpu"
printf "one process, %2d threads:    %7.2f s (CPU %.2f s)\n" "$cores" "$whole" "$whole_cpu"
for n in "${shard_counts[@]}"; do
  read -r t cpu < <(seconds "$root/scripts/encode-parallel.sh" -y "$work/db" "$work/par-$n.svc" "$n")
  cmp "$work/one.svc" "$work/par-$n.svc"
  printf "%2d shards (GNU parallel):   %7.2f s (CPU %.2f s)  speed-up %sx over 1 thread, %sx over %d threads; bytes identical\n" \
    "$n" "$t" "$cpu" "$(ratio "$single" "$t")" "$(ratio "$whole" "$t")" "$cores"
done
echo "(CPU time is the work done; where other processes share the cores, wall time overstates it)"
if [[ -x $build/bin/svc_memory_tests ]]; then
  "$build/bin/svc_memory_tests" | grep "peak resident"
fi
