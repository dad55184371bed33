// The in-loop filters of a B-frame: the deblocking strengths its macroblock decisions
// give (docs/codec.md, section 11.1) and the filtering of its reconstructed planes. Shared
// by the B-frame encoder and decoder, so both filter alike. Not part of the codec's
// interface.
#pragma once

#include "codec/bframe_state.h"
#include "codec/loop_filter.h"

namespace svc::codec::bframe {

// Boundary strengths on the 8x8 grid: 2 where either side is an intra macroblock, 1
// where either 8x8 block has coded levels or the two macroblocks' motion differs, else 0.
DeblockMap deblock_map(const FrameState& s);

// Deblocks the frame state's padded planes in place.
void deblock_planes(FrameState& s);

}  // namespace svc::codec::bframe
