#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# Fails when an `#include "..."` points up a layer. Layers, lowest first; a file may
# include from its own layer and those below:
#   0 decoder API   include/svc (status.h, types.h, limits.h, reader.h)
#   1 codec         codec/: codec/common, then codec/decoder, then codec/encoder
#   2 decoder       src/common, src/container, src/reader, src/capi (libsvc_decoder)
#   3 full library  src/database, src/spatial, src/output, src/encoder, src/metrics and the public
#                   encoder.h, metrics.h (libsvc)
#   4 baselines     src/baseline (libsvc_baseline)
#   5 samples       samples/ (samples/embed and samples/walkthrough: the decoder API and
#                   their own folder only; samples/command_line, the conventions every
#                   tool shares, uses the decoder API alone and counts as part of it)
#   6 bench         bench/
#   7 tools         tools/
#   8 tests         tests/
# Within the codec, common includes neither decoder nor encoder, and nothing that goes
# into the decoder library (decoder API, codec/common, codec/decoder, layer 2) includes
# an encoder header (codec/encoder/).
# The decoder library builds for Linux and Windows: among its files, only a platform file
# (*_posix.cc, *_windows.cc, chosen by src/common/CMakeLists.txt) includes an operating
# system header (unistd.h, fcntl.h, sys/*, windows.h, pthread.h and the like).
# An include is resolved as the compiler would: beside the including file, then under
# the include roots the build uses (include, the tree's root, src, samples, tools, bench,
# tests). An include that resolves nowhere is an error too.
# The libraries (include, codec, src) declare no thread_local: with MinGW-w64's emulated
# TLS a thread_local's storage is freed before its destructor runs at thread exit; a
# per-thread object lives in a codec/common/thread_slot.h slot instead.
# Usage: scripts/check-layers.sh [TREE_ROOT]   (default: this tree)
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root"

layer_names=("decoder API" codec decoder "full library" baselines samples bench tools tests)

layer_of() {
  case $1 in
    include/svc/encoder.h | include/svc/metrics.h) echo 3 ;;
    include/* | samples/command_line/*) echo 0 ;;
    codec/*) echo 1 ;;
    src/common/* | src/container/* | src/reader/* | src/capi/*) echo 2 ;;
    src/baseline/*) echo 4 ;;
    src/*) echo 3 ;;
    samples/*) echo 5 ;;
    bench/*) echo 6 ;;
    tools/*) echo 7 ;;
    tests/*) echo 8 ;;
    *) echo 9 ;;
  esac
}

# The codec's parts in order: 0 common, 1 decoder, 2 encoder; -1 outside the codec.
codec_part_of() {
  case $1 in
    codec/common/*) echo 0 ;;
    codec/decoder/*) echo 1 ;;
    codec/encoder/*) echo 2 ;;
    *) echo -1 ;;
  esac
}

# Whether a file goes into the decoder library, which holds no encoder code.
decoder_side() {
  case $1 in
    include/svc/encoder.h | include/svc/metrics.h) return 1 ;;
    include/* | codec/common/* | codec/decoder/* | src/common/* | src/container/* | src/reader/* | src/capi/*) return 0 ;;
    *) return 1 ;;
  esac
}

# The highest layer a file may include from.
limit_of() {
  case $1 in
    samples/embed/* | samples/embed_c/* | samples/walkthrough/*) echo 0 ;;
    *) layer_of "$1" ;;
  esac
}

resolve() {
  local from_dir=$1 name=$2 base
  for base in "$from_dir" include . src samples tools bench tests; do
    if [[ -f "$base/$name" ]]; then
      realpath -m --relative-to=. "$base/$name"
      return 0
    fi
  done
  return 1
}

violations=0
checked=0
while IFS= read -r file; do
  file=${file#./}
  limit=$(limit_of "$file")
  while IFS=: read -r line name; do
    checked=$((checked + 1))
    if ! target=$(resolve "$(dirname "$file")" "$name"); then
      echo "$file:$line: #include \"$name\" resolves to no file in the tree"
      violations=$((violations + 1))
      continue
    fi
    from_part=$(codec_part_of "$file") to_part=$(codec_part_of "$target")
    if ((from_part >= 0 && to_part > from_part)); then
      echo "$file:$line: #include \"$name\" ($target) points from one codec part into a later one (common, decoder, encoder)"
      violations=$((violations + 1))
      continue
    fi
    if [[ $target == codec/encoder/* ]] && decoder_side "$file"; then
      echo "$file:$line: #include \"$name\" ($target): the decoder library includes no encoder header"
      violations=$((violations + 1))
      continue
    fi
    layer=$(layer_of "$target")
    if ((layer > limit)) && [[ "$(dirname "$target")" != "$(dirname "$file")" ]]; then
      echo "$file:$line: #include \"$name\" ($target, ${layer_names[layer]}) points up from ${layer_names[limit]}"
      violations=$((violations + 1))
    fi
  done < <(grep -n -E '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$file" |
             sed -E 's/^([0-9]+):[^"]*"([^"]*)".*/\1:\2/')
done < <(find include codec src samples bench tools tests -type f \( -name '*.h' -o -name '*.cc' -o -name '*.cpp' \) 2>/dev/null | sort)

# Operating system headers in the decoder library outside its platform files.
system_headers='unistd\.h|fcntl\.h|sys/[a-z_/]+\.h|windows\.h|pthread\.h|dirent\.h|dlfcn\.h|io\.h'
platform_violations=0
while IFS= read -r file; do
  file=${file#./}
  decoder_side "$file" || continue
  case $file in *_posix.cc | *_windows.cc) continue ;; esac
  while IFS=: read -r line header; do
    echo "$file:$line: #include <$header> outside a platform file (*_posix.cc, *_windows.cc)"
    platform_violations=$((platform_violations + 1))
  done < <(grep -n -E "^[[:space:]]*#[[:space:]]*include[[:space:]]*<($system_headers)>" "$file" |
             sed -E 's/^([0-9]+):[^<]*<([^>]*)>.*/\1:\2/')
done < <(find include codec src -type f \( -name '*.h' -o -name '*.cc' \) 2>/dev/null | sort)

# thread_local declarations in the libraries (a comment mentioning the word is fine).
thread_local_violations=0
while IFS=: read -r file line _; do
  echo "$file:$line: thread_local in a library (use codec/common/thread_slot.h)"
  thread_local_violations=$((thread_local_violations + 1))
done < <(find include codec src -type f \( -name '*.h' -o -name '*.cc' \) -print0 2>/dev/null | sort -z |
           xargs -0 -r grep -n -E '^[^/]*\bthread_local\b' || true)

if ((violations > 0)); then
  echo "check-layers: $violations include(s) point up a layer"
fi
if ((platform_violations > 0)); then
  echo "check-layers: $platform_violations operating system header(s) in the decoder library outside its platform files"
fi
if ((thread_local_violations > 0)); then
  echo "check-layers: $thread_local_violations thread_local declaration(s) in the libraries"
fi
if ((violations + platform_violations + thread_local_violations > 0)); then
  exit 1
fi
echo "check-layers: $checked includes, all point down or across"
