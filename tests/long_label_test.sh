#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# The "long" tests stay out of the default run (plain `ctest`, as scripts/test.sh runs it),
# the default run keeps a sample of what they cover, and the documented command
# `ctest --test-dir BUILD -C long -L long` runs them and nothing else.
set -euo pipefail
build=$1
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
default=$(ctest --test-dir "$build" -N)
long=$(ctest --test-dir "$build" -N -C long -L long)
if grep -q "long\.\|EveryPairOfCodingTools" <<<"$default"; then
  fail "the default run holds a long test: $(grep "long\.\|EveryPairOfCodingTools" <<<"$default")"
fi
grep -q "RoundTrip.PairsOfCodingToolsCanBeSwitchedOff" <<<"$default" ||
  fail "the default run has no sample of tool pairs"
grep -q "long.every_pair_of_coding_tools_switched_off" <<<"$long" || fail "-C long -L long runs no long test"
if grep "Test *#" <<<"$long" | grep -vq " long\."; then
  fail "-C long -L long runs more than the long tests: $long"
fi
echo "default run: $(grep -c "Test *#" <<<"$default") tests; long run: $(grep -c "Test *#" <<<"$long")"
