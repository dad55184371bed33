#!/usr/bin/env bash
# Quick start, step one: install what is missing, build, and run the demo on the
# built-in sample scene.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
build/bin/svc demo "$@"
