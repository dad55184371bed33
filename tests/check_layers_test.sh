#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# scripts/check-layers.sh passes a tree whose includes point down and reports each
# include planted to point up: codec into src, the decoder into the encoder's API, the
# embedding sample into the full library, src into the samples, the codec's decoder part
# into its encoder part, its common part into its decoder part, and the reader into the
# codec's encoder part; and an operating system header in the decoder library outside a
# platform file, and a thread_local in a library.
set -euo pipefail
script=$1
tree=$(mktemp -d)
trap 'rm -rf "$tree"' EXIT
mkdir -p "$tree"/{include/svc,codec/common,codec/decoder,codec/encoder,src/common,src/reader,src/encoder} \
         "$tree"/samples/{embed,scene}
touch "$tree/include/svc/status.h" "$tree/include/svc/encoder.h" "$tree/src/common/bytes.h" \
      "$tree/samples/scene/scene.h" "$tree/codec/dct.h" "$tree/codec/common/quant.h" \
      "$tree/codec/decoder/intra_decoder.h" "$tree/codec/encoder/intra_search.h"
printf '#include "svc/status.h"\n#include "codec/dct.h"\n' >"$tree/codec/dct.cc"
printf '#include "codec/common/quant.h"\n' >"$tree/codec/decoder/intra_decoder.cc"
printf '#include "codec/common/quant.h"\n#include "codec/decoder/intra_decoder.h"\n' \
  >"$tree/codec/encoder/intra_encoder.cc"
printf '#include "codec/decoder/intra_decoder.h"\n' >"$tree/src/reader/face_decode.cc"
printf '#include "common/bytes.h"\n#include "svc/encoder.h"\n' >"$tree/src/encoder/encoder.cc"
printf '#include "svc/status.h"\n' >"$tree/samples/embed/main.cc"
printf '#include <unistd.h>\n#include "common/bytes.h"\n' >"$tree/src/common/file_source_posix.cc"
printf '#include <unistd.h>\n// no thread_local here: codec/common/thread_slot.h\n' >"$tree/src/encoder/shard_encode.cc"
"$script" "$tree" >/dev/null || { echo "a clean tree was refused"; exit 1; }

printf '#include "common/bytes.h"\n' >>"$tree/codec/dct.cc"
printf '#include <vector>\n#include "svc/encoder.h"\n' >"$tree/src/reader/reader.cc"
printf '#include "svc/encoder.h"\n' >>"$tree/samples/embed/main.cc"
printf '#include "scene/scene.h"\n' >>"$tree/src/common/bytes.h"
printf '#include "codec/encoder/intra_search.h"\n' >>"$tree/codec/decoder/intra_decoder.cc"
printf '#include "codec/decoder/intra_decoder.h"\n' >>"$tree/codec/common/quant.h"
printf '#include "codec/encoder/intra_search.h"\n' >>"$tree/src/reader/face_decode.cc"
printf '#include <sys/syscall.h>\n' >>"$tree/src/reader/face_decode.cc"
printf 'int& counter() {\n  static thread_local int n = 0;\n  return n;\n}\n' >>"$tree/codec/common/quant.h"
if out=$("$script" "$tree"); then
  echo "planted upward includes passed the check"
  exit 1
fi
echo "$out"
for expected in "codec/dct.cc:3:" "src/reader/reader.cc:2:" "samples/embed/main.cc:2:" "src/common/bytes.h:1:" \
                "codec/decoder/intra_decoder.cc:2:" "codec/common/quant.h:1:" "src/reader/face_decode.cc:2:" \
                "7 include(s) point up" "src/reader/face_decode.cc:3: #include <sys/syscall.h>" \
                "1 operating system header(s)" "codec/common/quant.h:3: thread_local in a library" \
                "1 thread_local declaration(s)"; do
  grep -qF "$expected" <<<"$out" || { echo "not reported: $expected"; exit 1; }
done
echo "check-layers reports every planted upward include"
