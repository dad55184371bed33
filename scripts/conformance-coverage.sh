#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# What of the decoder the conformance streams reach: builds svc-conformance with gcov
# instrumentation in build-coverage, decodes the suite through the plain references and
# then through every kernel level, and reports, per decoder source file, the lines
# never executed (gcovr). Needs gcovr (apt-get install gcovr).
#
#   scripts/conformance-coverage.sh [--per-stream] [REPORT (default build-coverage/coverage.txt)]
#
# --per-stream also decodes each stream on its own and prints, for each, the decoder
# lines it reaches and those no other stream reaches, with the functions they are in:
# what each stream is there for.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SVC_COVERAGE_BUILD_DIR:-$root/build-coverage}"
per_stream=0
if [[ "${1:-}" == --per-stream ]]; then
  per_stream=1
  shift
fi
report="${1:-$build/coverage.txt}"
if ! command -v gcovr >/dev/null; then
  echo "conformance-coverage.sh: gcovr not found (apt-get install gcovr)" >&2
  exit 2
fi
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS="--coverage -fprofile-update=atomic -O0" \
  -DCMAKE_EXE_LINKER_FLAGS=--coverage -DSVC_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" --target svc_conformance -j "${SVC_JOBS:-2}"
find "$build" -name '*.gcda' -delete
manifest="$root/tests/conformance/streams.txt"
# Each kernel level, as the test suite runs them (levels this machine lacks skip, 77).
SVC_CPU_MASK=0 "$build/bin/svc-conformance" "$manifest" --threads 1 --no-face-caches >/dev/null
for mask in 0x1 0x3 0x7 0x8; do
  SVC_CPU_MASK=$mask "$build/bin/svc-conformance" "$manifest" --threads 2 --prefetch >/dev/null || [[ $? == 77 ]]
done
# The decoder: the frame codec's common and decoder parts, the container and the reader;
# the NEON kernels are not built here.
filters=(--filter "$root/codec/common/" --filter "$root/codec/decoder/" --filter "$root/src/container/"
  --filter "$root/src/reader/" --exclude '.*/neon/.*')
gcovr --root "$root" --object-directory "$build" "${filters[@]}" --sort-uncovered --txt "$report" --print-summary
echo "line coverage per file, unreached lines listed: $report"

if ((per_stream)); then
  work="$build/per-stream"
  rm -rf "$work"
  mkdir -p "$work"
  while read -r name md5 _; do
    [[ -z "$name" || "$name" == \#* ]] && continue
    mkdir -p "$work/$name"
    ln -s "$root/tests/conformance/streams" "$work/$name/streams"
    echo "$name $md5" >"$work/$name/streams.txt"
    find "$build" -name '*.gcda' -delete
    SVC_CPU_MASK=0 "$build/bin/svc-conformance" "$work/$name/streams.txt" --threads 1 --no-face-caches >/dev/null
    "$build/bin/svc-conformance" "$work/$name/streams.txt" --threads 2 --prefetch >/dev/null
    gcovr --root "$root" --object-directory "$build" "${filters[@]}" --json "$work/$name.json" >/dev/null
  done <"$manifest"
  python3 "$root/scripts/conformance_reach.py" "$work"
fi
