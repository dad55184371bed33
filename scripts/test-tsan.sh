#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Builds the integration tests with ThreadSanitizer in build-tsan and runs the reader's
# access and threading tests under it. Any reported race fails the run.
#   scripts/test-tsan.sh [extra gtest filter, default Reader*]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SVC_TSAN_BUILD_DIR:-$root/build-tsan}"
filter="${1:-Reader*}"
jobs="${SVC_JOBS:-2}"

cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSVC_SANITIZE=thread -DSVC_BUILD_BENCH=OFF -DSVC_BUILD_FUZZERS=OFF
cmake --build "$build" --target svc_integration_tests -j "$jobs"

# halt_on_error: the first race fails the run; second_deadlock_stack for lock reports.
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 ${TSAN_OPTIONS:-}"
"$build/bin/svc_integration_tests" --gtest_filter="$filter"
