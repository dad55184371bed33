#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Checks the decoder library on Windows from any Linux machine: cross-builds
# svc-decode-digest for 64-bit Windows (SVC_DECODER_ONLY with
# cmake/x86_64-w64-mingw32.cmake: the decoder library and that program, no third-party
# library), makes a few .svc files with the native tools (one of them damaged, one cut
# short, and paths that do not open) and runs the native and the Windows program on them,
# the latter under Wine. Each prints one digest line per file over every face of every
# cell in every pixel format and row order, opened by path, from memory and through read
# callbacks; the check fails unless both print the same lines, errors included. The
# Windows program runs once with each x86 kernel set (SVC_CPU_MASK: AVX2, SSE4.1, SSE2,
# the plain references), all of which must decode the native program's bytes. Where GoogleTest's sources are installed
# (Debian: googletest), the codec's unit tests (tests/codec_*_test.cc) are cross-built too
# and run under Wine, with the best kernels and with the plain references alone.
# Installs the cross compiler, Wine and GoogleTest's sources (Debian 12:
# g++-mingw-w64-x86-64-posix, wine64, googletest) when the first two are missing; with
# --if-installed it exits 77 (skipped) instead, so that the test suite never downloads
# anything.
#
# Usage: scripts/check-windows.sh [--if-installed] [--native NATIVE_BUILD] [BUILD_DIR]
#   NATIVE_BUILD is the Linux build with svc, svc-scene and svc-decode-digest (default:
#   build in the tree); BUILD_DIR, for the Windows build, its .svc files and the Wine
#   prefix, defaults to build-windows in the tree.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if_installed=0
native=$root/build
build=$root/build-windows
while (($# > 0)); do
  case $1 in
    --if-installed) if_installed=1 ;;
    --native)
      native=$2
      shift
      ;;
    -*)
      echo "usage: $0 [--if-installed] [--native NATIVE_BUILD] [BUILD_DIR]" >&2
      exit 2
      ;;
    *) build=$1 ;;
  esac
  shift
done
native=$(realpath -m "$native")
build=$(realpath -m "$build")

# Debian's wine64 package installs the loader outside PATH; the wine package adds a
# wrapper on it.
find_wine() {
  command -v wine64 || { [[ -x /usr/lib/wine/wine64 ]] && echo /usr/lib/wine/wine64; } || command -v wine || true
}

compiler=x86_64-w64-mingw32-g++-posix
wine=$(find_wine)
if ! command -v "$compiler" >/dev/null || [[ -z $wine ]]; then
  if ((if_installed)); then
    echo "SKIPPED: $compiler or wine64 is not installed (apt-get install g++-mingw-w64-x86-64-posix wine64)"
    exit 77
  fi
  echo "installing: g++-mingw-w64-x86-64-posix wine64 googletest"
  sudo=""
  if [[ $(id -u) != 0 ]]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends g++-mingw-w64-x86-64-posix wine64 googletest
  wine=$(find_wine)
fi

for tool in svc svc-scene svc-decode-digest; do
  if [[ ! -x $native/bin/$tool ]]; then
    echo "$native/bin/$tool is missing: build the native tree first (or pass --native)" >&2
    exit 1
  fi
done

generator=()
if command -v ninja >/dev/null; then generator=(-G Ninja); fi
if [[ ! -f $build/CMakeCache.txt ]]; then
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DSVC_DECODER_ONLY=ON \
    -DCMAKE_TOOLCHAIN_FILE="$root/cmake/x86_64-w64-mingw32.cmake" >/dev/null
fi
targets=(svc-decode-digest)
if cmake --build "$build" --target help | grep -q '^svc_codec_tests'; then
  targets+=(svc_codec_tests)
else
  echo "note: no GoogleTest sources (apt-get install googletest): the codec's unit tests are left out"
fi
cmake --build "$build" --target "${targets[@]}" -j "${SVC_JOBS:-1}"

# A small database at two face sizes (40 is not a multiple of the 16-pixel macroblock),
# a copy with a few bytes flipped in the middle (a face fails, the others
# decode), one cut off halfway (the index is gone: the file does not open), a path that
# does not exist, a folder and a copy whose name is not ASCII (the C API takes UTF-8).
data=$build/data
rm -rf "$data"
mkdir -p "$data"
make_svc() {
  local name=$1 size=$2
  "$native/bin/svc-scene" "$data/$name-db" --grid 3,1,2 --face-size "$size" >/dev/null
  "$native/bin/svc" encode "$data/$name-db" -o "$data/$name.svc" -q 60 >/dev/null
}
make_svc small 32
make_svc odd 40
size=$(stat -c %s "$data/small.svc")
cp "$data/small.svc" "$data/damaged.svc"
printf '\xff\x00\xff\x00' | dd of="$data/damaged.svc" bs=1 seek=$((size / 2)) conv=notrunc status=none
head -c $((size / 2)) "$data/small.svc" >"$data/truncated.svc"
mkdir "$data/folder.svc"
cp "$data/odd.svc" "$data/café-ünï.svc"
files=(small.svc odd.svc damaged.svc truncated.svc missing.svc folder.svc café-ünï.svc)

cd "$data"
# Wine reads Unix file names and arguments in the locale's character set.
export LC_ALL=C.UTF-8
if ! native_out=$("$native/bin/svc-decode-digest" "${files[@]}"); then
  echo "check-windows: the native program failed:" >&2
  echo "$native_out" >&2
  exit 1
fi
echo "$native_out"
# Headless, quiet, with its own prefix (created on the first run, which takes a while).
export WINEPREFIX=$build/wine-prefix WINEDEBUG=-all
unset DISPLAY WAYLAND_DISPLAY
for mask in 0x7 0x3 0x1 0x0; do
  start=$(date +%s)
  status=0
  windows_out=$(SVC_CPU_MASK=$mask "$wine" "$build/bin/svc-decode-digest.exe" "${files[@]}" | tr -d '\r') || status=$?
  if ((status != 0)) || [[ $windows_out != "$native_out" ]]; then
    echo "check-windows: the Windows build (SVC_CPU_MASK=$mask, exit status $status) decodes differently:" >&2
    diff <(echo "$native_out") <(echo "$windows_out") >&2 || true
    exit 1
  fi
  echo "SVC_CPU_MASK=$mask: the same under Wine ($(($(date +%s) - start)) s)"
done
echo "check-windows: the Windows build under Wine decodes ${#files[@]} files exactly as the native one"

if [[ -x $build/bin/svc_codec_tests.exe ]]; then
  for mask in 0x7 0x0; do
    start=$(date +%s)
    if ! SVC_CPU_MASK=$mask "$wine" "$build/bin/svc_codec_tests.exe" --gtest_brief=1 >"$build/codec_tests.log" 2>&1; then
      tr -d '\r' <"$build/codec_tests.log" | grep -v '^\[ ' >&2
      echo "check-windows: the codec's unit tests fail under Wine (SVC_CPU_MASK=$mask)" >&2
      exit 1
    fi
    echo "SVC_CPU_MASK=$mask: the codec's unit tests pass under Wine ($(($(date +%s) - start)) s)"
  done
fi
