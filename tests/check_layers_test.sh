#!/usr/bin/env bash
# scripts/check-layers.sh passes a tree whose includes point down and reports each
# include planted to point up: codec into src, the decoder into the encoder's API, the
# embedding sample into the full library, src into the samples.
set -euo pipefail
script=$1
tree=$(mktemp -d)
trap 'rm -rf "$tree"' EXIT
mkdir -p "$tree"/{include/svc,codec,src/common,src/reader,src/encoder,samples/embed,samples/scene}
touch "$tree/include/svc/status.h" "$tree/include/svc/encoder.h" "$tree/src/common/bytes.h" \
      "$tree/samples/scene/scene.h" "$tree/codec/dct.h"
printf '#include "svc/status.h"\n#include "codec/dct.h"\n' >"$tree/codec/dct.cc"
printf '#include "common/bytes.h"\n#include "svc/encoder.h"\n' >"$tree/src/encoder/encoder.cc"
printf '#include "svc/status.h"\n' >"$tree/samples/embed/main.cc"
"$script" "$tree" >/dev/null || { echo "a clean tree was refused"; exit 1; }

printf '#include "common/bytes.h"\n' >>"$tree/codec/dct.cc"
printf '#include <vector>\n#include "svc/encoder.h"\n' >"$tree/src/reader/reader.cc"
printf '#include "svc/encoder.h"\n' >>"$tree/samples/embed/main.cc"
printf '#include "scene/scene.h"\n' >>"$tree/src/common/bytes.h"
if out=$("$script" "$tree"); then
  echo "planted upward includes passed the check"
  exit 1
fi
echo "$out"
for expected in "codec/dct.cc:3:" "src/reader/reader.cc:2:" "samples/embed/main.cc:2:" "src/common/bytes.h:1:" \
                "4 include(s) point up"; do
  grep -qF "$expected" <<<"$out" || { echo "not reported: $expected"; exit 1; }
done
echo "check-layers reports every planted upward include"
