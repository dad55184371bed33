#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Quick start, step two: build if needed and run the test suite. Arguments go to ctest;
# the tests too long for the default run: scripts/test.sh -C long -L long
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
