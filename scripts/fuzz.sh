#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Builds the libFuzzer targets with clang under AddressSanitizer and
# UndefinedBehaviorSanitizer (build-fuzz) and runs each for a given time, starting from
# the seed corpus in tests/fuzz/corpus. Needs clang: SVC_WITH_CLANG=1 scripts/install-deps.sh
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET (default 60)] [TARGET ...]
#   targets (default all, one after the other):
#     container      an .svc file: open, then decode every face (container and frame parsers)
#     frame          one coded frame (I, B or depth) of a small size against synthetic references
#     alloc_failure  an .svc file decoded through svc::Reader while one allocation fails
#                    (or every one from some point on): errors, no leak, the next calls work
#     threads        an .svc file decoded by a reader with prefetch and small caches from
#                    four threads at once, one closing it part-way: the sequential decode's
#                    results, kCancelled after close, no hang
#
# The targets that take whole .svc files (container, alloc_failure, threads) are seeded
# with tests/fuzz/corpus/container and, when present, the conformance streams
# (tests/conformance/streams/*.svc); each target also with tests/fuzz/corpus/<target>.
#
# New inputs found go to build-fuzz/corpus/<target> (the seed corpus is not modified);
# crashes to build-fuzz/findings/<target>/. Any finding fails the run; add the input
# to tests/fuzz/corpus/<target>/ once fixed, so the test suite replays it.
# SVC_FUZZ_JOBS=N runs N workers per target (default 1); SVC_FUZZ_SKIP_BUILD=1 skips
# the build (e.g. for a second instance running another target at the same time).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SVC_FUZZ_BUILD_DIR:-$root/build-fuzz}"
seconds="${1:-60}"
shift || true
targets=("$@")
if ((${#targets[@]} == 0)); then targets=(container frame alloc_failure threads); fi
for t in "${targets[@]}"; do
  case "$t" in
    container | frame | alloc_failure | threads) ;;
    *) echo "fuzz.sh: unknown target $t (container, frame, alloc_failure, threads)" >&2; exit 2 ;;
  esac
done

if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found; run SVC_WITH_CLANG=1 scripts/install-deps.sh" >&2
  exit 2
fi

sanitizers="address,undefined"
# SVC_FUZZ_SKIP_BUILD=1: reuse the build (e.g. to run targets in parallel).
if [[ "${SVC_FUZZ_SKIP_BUILD:-0}" != 1 ]]; then
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER=clang++ -DSVC_BUILD_FUZZERS=ON -DSVC_BUILD_TESTS=OFF -DSVC_BUILD_BENCH=OFF \
  "-DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link,$sanitizers -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=$sanitizers" >/dev/null
for t in "${targets[@]}"; do
  cmake --build "$build" --target "svc_${t}_fuzzer" -j "${SVC_JOBS:-2}"
done
fi

export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
status=0
for t in "${targets[@]}"; do
  work="$build/corpus/$t"
  findings="$build/findings/$t"
  mkdir -p "$work" "$findings"
  echo "fuzzing $t for ${seconds}s"
  # -rss_limit_mb and -malloc_limit_mb turn an allocation the caps should have stopped
  # into a finding; -timeout does the same for a hang. A whole seed file of a few dozen
  # faces decodes in about 1.5 s under the sanitizers, and several times slower on a
  # loaded machine: SVC_FUZZ_TIMEOUT (default 60 s) leaves room for that, and only a unit
  # that slow is reported as slow (-report_slow_units), so that slow valid seeds are not
  # findings.
  parallel=()
  if (("${SVC_FUZZ_JOBS:-1}" > 1)); then parallel=(-jobs="$SVC_FUZZ_JOBS" -workers="$SVC_FUZZ_JOBS"); fi
  seeds=()
  if [[ -d "$root/tests/fuzz/corpus/$t" ]]; then seeds+=("$root/tests/fuzz/corpus/$t"); fi
  if [[ "$t" != frame ]]; then
    if [[ "$t" != container ]]; then seeds+=("$root/tests/fuzz/corpus/container"); fi
    if [[ -d "$root/tests/conformance/streams" ]]; then seeds+=("$root/tests/conformance/streams"); fi
  fi
  rc=0
  "$build/bin/svc_${t}_fuzzer" "$work" "${seeds[@]}" \
    -max_total_time="$seconds" -timeout="${SVC_FUZZ_TIMEOUT:-60}" -report_slow_units="${SVC_FUZZ_TIMEOUT:-60}" -rss_limit_mb=2048 -malloc_limit_mb=512 -max_len=65536 \
    -artifact_prefix="$findings/" -print_final_stats=1 "${parallel[@]}" >"$build/fuzz-$t.log" 2>&1 || rc=$?
  grep -E "ERROR|SUMMARY|stat::number_of_executed_units|stat::peak_rss|Done [0-9]+ runs" "$build/fuzz-$t.log" || true
  echo "$t: corpus $(ls "$work" | wc -l) inputs; exit status $rc"
  if [[ $rc != 0 ]] || ls "$findings" | grep -q .; then
    echo "fuzz.sh: $t found a problem; see $findings and $build/fuzz-$t.log" >&2
    status=1
  fi
done
exit "$status"
