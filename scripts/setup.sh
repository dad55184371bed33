#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Quick start, step one: install what is missing, build, and run the demo on the
# built-in sample scene.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
build/bin/svc demo "$@"
