#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# The decoder library holds no encoder code: no symbol that the codec's encoder part
# (codec/encoder, object library svc_codec_encoder) defines, and no symbol named like
# encoder work (encoding, forward transforms, quantization, SAD/SATD, searches, rate
# estimates, syntax writers), is defined in libsvc_decoder. As a control, the full
# library libsvc must show such symbols, so the check can fail.
# Usage: decoder_symbols_test.sh DECODER_LIBRARY FULL_LIBRARY ENCODER_OBJECT_DIR
set -euo pipefail
decoder=$1 full=$2 encoder_objects=$3

# Strong definitions only: inline functions of shared headers are weak (W) in both.
strong_symbols() { nm --defined-only "$@" 2>/dev/null | awk '$2 ~ /^[TDBR]$/ {print $3}' | sort -u; }
defined_symbols() { nm --defined-only "$@" 2>/dev/null | awk 'NF == 3 {print $3}' | sort -u; }

mapfile -t objects < <(find "$encoder_objects" -name '*.o' | sort)
((${#objects[@]} > 0)) || { echo "no object files under $encoder_objects"; exit 1; }
encoder_defined=$(strong_symbols "${objects[@]}")
[[ -n $encoder_defined ]] || { echo "the encoder objects define no symbol"; exit 1; }

decoder_defined=$(defined_symbols "$decoder")
shared=$(comm -12 <(echo "$encoder_defined") <(echo "$decoder_defined"))
if [[ -n $shared ]]; then
  echo "libsvc_decoder defines symbols of the codec's encoder part:"
  c++filt <<<"$shared" | head -20
  exit 1
fi

# Names of encoder work in the codec's namespace (demangled).
pattern='svc::codec::([a-z_]+::)*(encode_|[A-Za-z]*Encoder|forward_|quantize_block|rdoq|sad_|satd|choose_|write_|[a-z_]*_bits\(|[A-Za-z]*Search|search_|bit_cost|make_cost_table|[a-z_]*lambda)'
named() { nm --defined-only -C "$1" 2>/dev/null | awk 'NF >= 3 {$1 = ""; $2 = ""; print}' | grep -E "$pattern" | sort -u || true; }
found=$(named "$decoder")
if [[ -n $found ]]; then
  echo "libsvc_decoder defines encoder-named symbols:"
  head -20 <<<"$found"
  exit 1
fi
control=$(named "$full")
[[ -n $control ]] || { echo "the control found no encoder symbol in $full: the check cannot fail"; exit 1; }
encoder_in_full=$(comm -12 <(echo "$encoder_defined") <(defined_symbols "$full") | wc -l)
((encoder_in_full > 0)) || { echo "the control found none of the encoder objects' symbols in $full"; exit 1; }
echo "libsvc_decoder: none of the $(wc -l <<<"$encoder_defined") encoder symbols; libsvc: $encoder_in_full of them"
