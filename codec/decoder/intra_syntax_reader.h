// SPDX-License-Identifier: BSD-2-Clause
// Reading of intra block syntax (docs/codec.md 3.1, 3.5, 3.3): prediction modes, chroma
// modes with CfL, transform types, and the blocks and split flags of a luma macroblock,
// for intra frames and B-face intra macroblocks.
// Errors: functions returning bool give false on syntax no encoder produces; none reads
// outside its input.
#pragma once

#include <cstdint>

#include "codec/common/intra_macroblock.h"
#include "codec/decoder/range_decoder.h"

namespace svc::codec {

// The prediction mode of a block of `size` given its most probable modes.
int decode_intra_mode(RangeDecoder& decoder, IntraModeContexts& contexts, TransformSize size,
                      const ModeCandidates& candidates);

// Cb: the CfL flag (context `cfl_context`, the left and above Cb blocks using CfL), then
// Cb's alpha (never 0) or the regular mode with `candidates`. Cr: nothing unless `cb`,
// its Cb block's mode, is CfL; then Cr's alpha (possibly 0). Returns `cb`'s mode for a
// Cr block. Never fails: every bit pattern gives a valid mode and alpha.
ChromaMode decode_chroma_mode(RangeDecoder& decoder, CflContexts& cfl, IntraModeContexts& modes, int cfl_context,
                              const ModeCandidates& candidates, ChromaPlane plane, const ChromaMode& cb);

// A block's transform type (DCT_DCT when the contexts are not enabled).
TransformType decode_transform_type(RangeDecoder& decoder, TransformTypeContexts& contexts, TransformSize size,
                                    int mode);

}  // namespace svc::codec

namespace svc::codec::intra {

// A block's syntax as read: its mode (chroma: kCflMode with `cfl_alpha`), its
// non-zero levels in scan order and its transform type (DCT_DCT without levels).
struct BlockSyntax {
  int mode = kDcMode;
  int cfl_alpha = 0;
  TransformType transform_type = TransformType::kDctDct;
  int count = 0;
  BlockLevel levels[kMaxTransformArea];
};

// Reads the mode and levels of a luma block of `size` at (x0, y0) of a plane whose
// neighbours `state` describes; the caller marks the block. Returns false on invalid
// levels.
bool read_block_syntax(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int x0, int y0,
                       TransformSize size, BlockSyntax* out);
// Reads an 8x8 chroma block's mode (codec/cfl.h: the CfL flag and alpha, or the regular
// mode) and levels; a Cb block's mode goes to `cb`, which the Cr block at the same place
// reads. The caller marks the block. Returns false on invalid levels.
bool read_chroma_block_syntax(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int x0,
                              int y0, ChromaPlane plane, ChromaMode* cb, BlockSyntax* out);

// Receives each block of a luma macroblock as its syntax comes up; must read the block
// and mark it in the plane state before returning (the next split flag's context looks
// at it). Returns false on invalid syntax.
class BlockReader {
 public:
  virtual bool read(int x0, int y0, TransformSize size) = 0;

 protected:
  ~BlockReader() = default;
};

// Reads the split and halves flags of luma macroblock (mbx, mby) and hands each block to
// `reader` in coding order; `partition` receives the partition. False when the
// reader fails.
bool read_luma_macroblock(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int mbx, int mby,
                          BlockReader& reader, LumaPartition* partition);

}  // namespace svc::codec::intra
