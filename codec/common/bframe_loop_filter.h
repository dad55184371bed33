// SPDX-License-Identifier: BSD-2-Clause
// The in-loop filters of a B-face: the deblocking strengths its macroblock decisions
// give (docs/codec.md, section 5.8.1) and the filtering of its reconstructed planes. Shared
// by the B-face encoder and decoder, so both filter alike. Not part of the codec's
// interface.
#pragma once

#include "codec/common/bframe_state.h"
#include "codec/common/cdef.h"
#include "codec/common/loop_filter.h"

namespace svc::codec::bframe {

// Boundary strengths on the 8x8 grid: 2 where either side is an intra macroblock, 1
// where either 8x8 block has coded levels or the two macroblocks' motion differs, else 0.
DeblockMap deblock_map(const FrameState& s);

// Deblocks the frame state's padded planes in place.
void deblock_planes(FrameState& s);

// Per luma 8x8 block, row-major: 1 where CDEF leaves the block alone, a block of an
// inter or skipped macroblock without coded levels in it or in the macroblock's chroma.
std::vector<uint8_t> cdef_skip_map(const FrameState& s);

// The frame state's padded planes as the filters see them.
std::array<PlaneView, 3> plane_views(FrameState& s);

// Applies CDEF with `params` to the frame state's padded planes in place.
void cdef_planes(FrameState& s, const CdefParams& params);

}  // namespace svc::codec::bframe
