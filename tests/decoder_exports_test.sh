#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# The shared decoder library exports its public API alone: the C API's svc_* functions
# and the C++ API of svc/ (svc::Reader, svc::Status, ...), besides the instantiations of
# standard-library templates that libstdc++ keeps visible; no internal namespace
# (svc::codec, svc::reader_internal), no encoder, image-library or FFmpeg symbol. And it
# is marked never to be unloaded: threads that decoded call back into it when they end.
# Usage: decoder_exports_test.sh SHARED_DECODER_LIBRARY
set -euo pipefail
library=$1
test_name="decoder exports"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "$test_name: $*" >&2
  exit 1
}

readelf -d "$library" | grep -q 'Flags:.*NODELETE' ||
  fail "$library can be unloaded by dlclose (link it with -z nodelete)"

nm -D --defined-only "$library" | awk 'NF >= 3 {print $3}' | sort -u >"$work/mangled"
c++filt <"$work/mangled" >"$work/names"
[[ -s "$work/names" ]] || fail "$library exports nothing"

# Every API entry point an embedder calls is there.
for wanted in svc_reader_open_file svc_reader_open_callbacks svc_reader_decode_face svc_reader_last_error \
              svc_reader_decode_face_depth 'svc::Reader::decode_face_depth_into(' \
              'svc::Reader::open(std::unique_ptr<svc::ByteSource' 'svc::Reader::decode_face_into(' \
              'svc::Status::to_string' 'svc::memory_source('; do
  grep -qF "$wanted" "$work/names" || fail "the API symbol $wanted is not exported"
done

# What else is exported must be public API or standard-library instantiations.
grep -vE '^svc_[a-z_]+$' "$work/names" |
  grep -vE '^((typeinfo|typeinfo name|vtable|guard variable) for )?svc::(Reader|Status|ByteSource|memory_source|open_file_source|default_reader_settings|error_code_name|face_name|face_from_name|cell_label|face_label|pixel_row_bytes|pixel_plane_rows)\b' |
  grep -vE '^((typeinfo|typeinfo name|vtable|guard variable) for |[a-z]+ )?std::' >"$work/unexpected" || true
if [[ -s "$work/unexpected" ]]; then
  head -20 "$work/unexpected" >&2
  fail "$(wc -l <"$work/unexpected") exported symbols are not the public API (above)"
fi
if grep -E 'svc::(codec|reader_internal|dsp)::|[Ee]ncode|OpenImageIO|OIIO|Imf_|Imath|av_|avcodec|sws_' "$work/names" |
  grep -vE '^std::|svc::Reader::Impl' >"$work/internal"; then
  head -20 "$work/internal" >&2
  fail "internal or encoder symbols are exported (above)"
fi
echo "$test_name: $(wc -l <"$work/names") exported symbols, all public API"
