#!/usr/bin/env bash
# Sharded encoding on this machine: the speed-up of N shards run by GNU parallel (one
# thread each, scripts/encode-parallel.sh) over one process using every core and over
# one single-threaded process, each merged file checked against the one-process bytes;
# then the peak memory of the 100,000-face encode (build/bin/svc_memory_tests).
#
#   bench/shard-speedup.sh [BUILD_DIR] [N...]     (default: build, 2 and the core count)
#
# The database: `svc-scene --grid 9,1,9 --face-size 128` (the hall, 486 faces).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath "${1:-$root/build}")
shift || true
cores=$(nproc)
shard_counts=("$@")
((${#shard_counts[@]})) || shard_counts=(2 "$cores")
export SVC=$build/bin/svc
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

seconds() {
  local start end
  start=$(date +%s.%N)
  "$@" >/dev/null
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { print b - a }'
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }

"$build/bin/svc-scene" "$work/db" --grid 9,1,9 --face-size 128 --quiet
echo "machine: $cores cores; database: svc-scene --grid 9,1,9 --face-size 128 (486 faces)"
single=$(seconds "$SVC" encode "$work/db" -o "$work/single.svc" --threads 1 --quiet)
whole=$(seconds "$SVC" encode "$work/db" -o "$work/one.svc" --threads "$cores" --quiet)
cmp "$work/single.svc" "$work/one.svc"
printf "one process, 1 thread:      %7.2f s\n" "$single"
printf "one process, %2d threads:    %7.2f s\n" "$cores" "$whole"
for n in "${shard_counts[@]}"; do
  t=$(seconds "$root/scripts/encode-parallel.sh" "$work/db" "$work/par-$n.svc" "$n")
  cmp "$work/one.svc" "$work/par-$n.svc"
  printf "%2d shards (GNU parallel):   %7.2f s  speed-up %sx over 1 thread, %sx over %d threads; bytes identical\n" \
    "$n" "$t" "$(ratio "$single" "$t")" "$(ratio "$whole" "$t")" "$cores"
done
if [[ -x $build/bin/svc_memory_tests ]]; then
  "$build/bin/svc_memory_tests" | grep "peak resident"
fi
