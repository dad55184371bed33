// SPDX-License-Identifier: BSD-2-Clause
// An intra frame (an I-face) as both sides see it: its header constants, its packed
// semi-decoded form (CoefficientFrame) and the reconstruction of that form into pixels.
// The syntax is specified in docs/codec.md; reading it is codec/decoder/intra_decoder.h,
// writing it codec/encoder/intra_encoder.h. Pure computation: no files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/common/cdef.h"
#include "codec/common/coefficient_contexts.h"
#include "codec/common/quant.h"
#include "codec/common/transform_type.h"
#include "svc/types.h"

namespace svc::codec {

// Byte 3 of every frame header: the in-loop filters the frame uses (docs/codec.md,
// section 5.8). A decoder rejects other bits.
inline constexpr uint8_t kLoopFilterDeblocking = 1;
inline constexpr uint8_t kLoopFilterCdef = 2;
inline constexpr uint8_t kLoopFilterKnownBits = kLoopFilterDeblocking | kLoopFilterCdef;
// Flags byte bit 2, intra frames only: residuals use ResidualMatrix::kWeighted.
inline constexpr uint8_t kIntraWeightedMatrix = 4;
// Flags byte bit 3, intra frames and B-faces: intra blocks with levels code their
// transform type (docs/codec.md 3.5); without it every block is DCT_DCT.
inline constexpr uint8_t kTransformTypesFlag = 8;

// Byte 0 of every frame payload: the frame type in bit 7 (0 intra, 1 bidirectional) and
// the syntax version in bits 0-6. An intra payload goes on with its qindex and its flags
// byte (loop filters, matrix, transform types).
inline constexpr uint8_t kBidirectionalTypeBit = 0x80;
inline constexpr uint8_t kSyntaxVersionMask = 0x7F;
inline constexpr int kQIndexByte = 1;
inline constexpr int kIntraFlagsByte = 2;
inline constexpr int kFrameHeaderBytes = 3;
// The intra syntax the encoder writes, and the first a decoder reads: format 1.0's
// (docs/codec.md 1.1).
inline constexpr uint8_t kIntraSyntaxVersion = 16;
inline constexpr uint8_t kIntraSyntaxFirst = 16;
// Largest width or height parse_intra_frame accepts (a cap for untrusted input).
inline constexpr int kMaxFrameDimension = 16384;

// The partitions, prediction modes and quantized DCT levels of an intra frame in a
// compact sparse form: the state after entropy decoding ("semi-decoded"), cached by the
// runtime. Dequantization (quant.h, dequantize_level), prediction and the inverse
// transforms are deferred to reconstruct_intra_frame.
// Immutable once built, so it may be shared between threads.
struct CoefficientFrame {
  int width = 0;
  int height = 0;
  int qindex = 0;
  uint8_t loop_filters = 0;                                // kLoopFilter* bits of the header
  ResidualMatrix residual_matrix = ResidualMatrix::kFlat;  // header bit kIntraWeightedMatrix
  CdefParams cdef;                                         // when loop_filters has kLoopFilterCdef
  // Per luma macroblock in raster order: its partition (intra_macroblock.h,
  // LumaPartition: bit 0 set when it splits into four 8x8 blocks, else one 16x16 block,
  // two halves or four strips; docs/codec.md 3.1 and runtime.md).
  std::vector<uint16_t> luma_partitions;
  // Per transform block, in coding order (the luma blocks of every macroblock in turn,
  // then the 8x8 blocks of Cb, then of Cr, each in raster order): the number of non-zero
  // levels, 0..256.
  std::vector<uint16_t> block_counts;
  // Per block in the same order: its intra prediction mode, 0..kIntraModes - 1
  // (codec/intra_prediction.h; a Cr block repeats its Cb block's mode), or for a chroma
  // block using CfL its alpha as cfl_mode_byte(alpha) (codec/cfl.h: 35..67; a Cr block
  // holds its own alpha).
  std::vector<uint8_t> block_modes;
  // The transform type and non-zero levels of each block with levels in turn, each
  // block's as a whole-byte stream (codec/level_stream.h, docs/runtime.md).
  std::vector<uint8_t> levels;

  // Heap and object bytes held.
  size_t memory_bytes() const;

  // Appends a block's transform type and non-zero levels (natural positions, in
  // increasing scan order of `size`; |level| 1..4095); nothing when count is 0.
  void append_levels(const BlockLevel* block_levels, int count, TransformSize size,
                     TransformType type = TransformType::kDctDct);
  // Reads the transform type into *type and the `count` levels of a block of `size`
  // stored at byte *offset into positions (natural) and values, and moves *offset past
  // them. Returns how many it read: fewer than `count` only for frames not built by this
  // codec (never reads outside `levels`). *type is kDctDct when none was read.
  int read_levels(size_t* offset, int count, TransformSize size, int* positions, int* values,
                  TransformType* type) const;
};

// The levels of a CoefficientFrame as parsing decoded them, before packing: the caller
// that parses a frame and reconstructs it at once hands them to reconstruct_intra_frame,
// which then skips unpacking CoefficientFrame::levels (the packed form stays what a cache
// keeps). Only valid with the frame parsed alongside it.
struct DecodedLevels {
  // Every block's non-zero levels, block after block in coding order, each block's in
  // increasing scan order (natural positions).
  std::vector<BlockLevel> levels;
  // Per block with levels, in the same order: its transform type.
  std::vector<TransformType> types;
};

// 8x8 block grid of a frame of the given size (macroblock-padded planes): chroma blocks
// are 8x8; luma macroblocks hold 2 x 2 of these units, coded as their partitions say.
struct BlockLayout {
  int luma_blocks_x = 0, luma_blocks_y = 0;      // padded luma width / 8, height / 8
  int chroma_blocks_x = 0, chroma_blocks_y = 0;  // half of the above
  // The blocks of a frame of 8x8 luma blocks only (a capacity hint).
  int block_count() const { return luma_blocks_x * luma_blocks_y + 2 * chroma_blocks_x * chroma_blocks_y; }
};
BlockLayout block_layout(int width, int height);

// Prediction plus inverse transforms of parsed coefficients into pixels, then the in-loop
// filters the frame header asks for (bit-exact). `out` is resized; a frame not built by
// parse_intra_frame or encode_intra_frame gives some pixels of the right size, never a
// crash. `decoded` (optional): the levels parse_intra_frame unpacked while building
// `coefficients`, read instead of the packed ones (same pixels); ignored when its counts
// do not match the frame's.
void reconstruct_intra_frame(const CoefficientFrame& coefficients, ImageYCbCr420* out,
                             const DecodedLevels* decoded = nullptr);

}  // namespace svc::codec
