#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Installs missing dependencies, then configures and builds svc into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
if [[ ! -f build/build.ninja ]]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
cmake --build build -j"$(nproc)"
