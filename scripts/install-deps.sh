#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Installs the Debian 12 packages svc builds against, if any are missing.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config
  # The conformance suite records MD5s of decoded streams (tests/conformance).
  nettle-dev
  libopenimageio-dev openimageio-tools libopenexr-dev libglm-dev
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev
  libgtest-dev libgmock-dev libbenchmark-dev nlohmann-json3-dev libcli11-dev
  ffmpeg clang-format-14
  # scripts/encode-parallel.sh runs the shards of an encode with GNU parallel.
  parallel
  # tests/renderer_manifest_test.sh runs docs/input-format.md's manifest writer; the C
  # API's Python example (docs/embedding.md) decodes into NumPy arrays.
  python3 python3-numpy
  # Photographic sample scenes: scripts/fetch-textures.sh extracts the game textures.
  openarena-081-textures unzip
  # svc-viewer (samples/viewer): OpenGL via GLFW and epoxy; its test renders in Xvfb with Mesa.
  libglfw3-dev libepoxy-dev xvfb xauth libgl1-mesa-dri
)
# The test suite checks the AArch64 NEON kernels cross-built, under qemu
# (scripts/check-neon.sh). Without recommends: qemu-user recommends qemu-user-binfmt,
# which registers handlers with the kernel, something a container may refuse. It also
# checks the decoder library cross-built for Windows, under Wine (scripts/check-windows.sh;
# wine64 alone, without the 32-bit half and the desktop integration it recommends), with
# the codec's unit tests built from GoogleTest's sources.
lean_packages=(g++-aarch64-linux-gnu qemu-user g++-mingw-w64-x86-64-posix wine64 googletest)
# scripts/encode-slurm.sh and the one-node cluster of scripts/slurm-localhost.sh.
if [[ "${SVC_WITH_SLURM:-0}" == 1 ]]; then
  packages+=(slurm-wlm munge)
fi
if [[ "${SVC_WITH_CLANG:-0}" == 1 ]]; then
  packages+=(clang libclang-rt-14-dev)
fi

missing_of() {
  local p
  for p in "$@"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      echo "$p"
    fi
  done
}
mapfile -t missing < <(missing_of "${packages[@]}")
mapfile -t missing_lean < <(missing_of "${lean_packages[@]}")
if ((${#missing[@]} + ${#missing_lean[@]} == 0)); then
  exit 0
fi

all_missing=("${missing[@]}" "${missing_lean[@]}")
echo "installing: ${all_missing[*]}"
sudo=""
if [[ $(id -u) != 0 ]]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
if ((${#missing[@]} > 0)); then
  $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi
if ((${#missing_lean[@]} > 0)); then
  $sudo apt-get install -y -qq --no-install-recommends "${missing_lean[@]}" >/dev/null
fi
