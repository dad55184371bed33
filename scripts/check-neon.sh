#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Checks the AArch64 NEON kernel variants on any Linux machine: cross-builds
# svc-checkkernels for AArch64 (SVC_KERNELS_ONLY with cmake/aarch64-linux-gnu.cmake: the
# codec layer, the flow kernels and the checker, no third-party library) and runs it under
# qemu-aarch64, which compares every NEON variant with its plain reference bit for bit.
# Exits non-zero on any mismatch. Installs the cross compiler and qemu (Debian 12:
# g++-aarch64-linux-gnu, qemu-user) when missing; with --if-installed it exits 77
# (skipped) instead, so that the test suite never downloads anything.
#
# --bench then also prints the speed ratios. They are timed under emulation: qemu
# translates each instruction, so the ratios say little about Arm hardware.
#
# Usage: scripts/check-neon.sh [--if-installed] [--bench] [BUILD_DIR] [-- CHECKER_ARGS...]
#   BUILD_DIR defaults to build-aarch64 in the tree; CHECKER_ARGS go to svc-checkkernels
#   (e.g. --seed N, --kernel NAME).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if_installed=0
bench=0
build=$root/build-aarch64
checker_args=()
while (($# > 0)); do
  case $1 in
    --if-installed) if_installed=1 ;;
    --bench) bench=1 ;;
    --)
      shift
      checker_args=("$@")
      break
      ;;
    -*)
      echo "usage: $0 [--if-installed] [--bench] [BUILD_DIR] [-- CHECKER_ARGS...]" >&2
      exit 2
      ;;
    *) build=$1 ;;
  esac
  shift
done

compiler=aarch64-linux-gnu-g++
sysroot=/usr/aarch64-linux-gnu
if ! command -v "$compiler" >/dev/null || ! command -v qemu-aarch64 >/dev/null; then
  if ((if_installed)); then
    echo "SKIPPED: $compiler or qemu-aarch64 is not installed (apt-get install g++-aarch64-linux-gnu qemu-user)"
    exit 77
  fi
  echo "installing: g++-aarch64-linux-gnu qemu-user"
  sudo=""
  if [[ $(id -u) != 0 ]]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends g++-aarch64-linux-gnu qemu-user
fi

generator=()
if command -v ninja >/dev/null; then generator=(-G Ninja); fi
if [[ ! -f $build/CMakeCache.txt ]]; then
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DSVC_KERNELS_ONLY=ON \
    -DCMAKE_TOOLCHAIN_FILE="$root/cmake/aarch64-linux-gnu.cmake" >/dev/null
fi
cmake --build "$build" --target svc-checkkernels -j "${SVC_JOBS:-1}"

checker=(qemu-aarch64 -L "$sysroot" "$build/bin/svc-checkkernels")
"${checker[@]}" "${checker_args[@]}"
if ((bench)); then
  echo "speed ratios under qemu-aarch64 emulation (not timings of Arm hardware):"
  "${checker[@]}" --bench "${checker_args[@]}"
fi
