// SPDX-License-Identifier: BSD-2-Clause
// Internal to svc_baseline: which frames each coded frame depends on, as recorded in the
// index, so that one frame can be decoded on its own.
#pragma once

#include "baseline/baseline.h"

namespace svc::baseline::detail {

// MPEG-2: B-pictures are never references; P predicts from the previous anchor and B
// from the two anchors before it in decode order (open GOPs included).
void link_mpeg2_references(EncodedSequence* sequence);

// Codecs whose reference lists are not parsed (H.264, HEVC, AV1): every frame depends on
// the latest reference frame before it in decode order, back to a keyframe, which is an
// upper bound on what it needs. A leading frame of an open GOP (decoded after a keyframe
// but shown before it) also depends on the frames before that keyframe, back to the
// previous keyframe. Frames shown after a keyframe never depend on its leading frames
// (HEVC's rule for RASL pictures, which x264's open GOPs keep too; the random-access
// tests check decoded pixels). For H.264 and HEVC, frames whose NAL header marks them as
// non-reference (nal_ref_idc 0; the _N picture types) are left out of every chain.
void link_chained_references(EncodedSequence* sequence);

// False when the first slice of an H.264 or HEVC packet (Annex B) is marked as not used
// for reference; true otherwise and for every other codec.
bool is_reference_picture(const std::string& decoder, const uint8_t* data, size_t size);

}  // namespace svc::baseline::detail
