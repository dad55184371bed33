// SPDX-License-Identifier: BSD-2-Clause
// Writing of intra block syntax (docs/codec.md 3.1, 3.5, 3.3) and its bit estimates at
// the contexts' current probabilities, mirrored by codec/decoder/intra_syntax_reader.h:
// prediction modes, chroma modes with CfL, transform types, and the blocks and split
// flags of a luma macroblock.
#pragma once

#include <algorithm>
#include <array>
#include <concepts>
#include <cstdint>
#include <type_traits>

#include "codec/common/intra_macroblock.h"
#include "codec/encoder/range_encoder.h"

namespace svc::codec {

// The rank of a mode that is no most probable one among the modes that are not.
int rank_among_others(const ModeCandidates& candidates, int mode);

// Calls bit(context, value) on every bit of a block's mode in coding order: whether it
// is a most probable mode, which one, or its rank among the other modes in
// kRemainderBits bits down a binary tree of contexts.
template <class Contexts, class Bit>
requires std::same_as<std::remove_const_t<Contexts>, IntraModeContexts>
void for_each_mode_bit(Contexts& contexts, TransformSize size, const ModeCandidates& candidates, int mode,
                       Bit&& bit) {
  const auto size_class = static_cast<size_t>(mode_size_class(size));
  const auto context = static_cast<size_t>(candidates.context);
  const auto found = std::find(candidates.begin(), candidates.end(), mode);
  bit(contexts.is_most_probable[size_class][context], found != candidates.end() ? 1 : 0);
  if (found != candidates.end()) {
    const int index = static_cast<int>(found - candidates.begin());
    auto& index_bits = contexts.most_probable_index[size_class][context];
    bit(index_bits[0], index > 0 ? 1 : 0);
    if (index > 0) bit(index_bits[1], index > 1 ? 1 : 0);
    return;
  }
  const int rank = rank_among_others(candidates, mode);
  size_t node = 1;
  for (int b = kRemainderBits - 1; b >= 0; --b) {
    const int value = (rank >> b) & 1;
    bit(contexts.remainder[node - 1], value);
    node = 2 * node + static_cast<size_t>(value);
  }
}

void encode_intra_mode(RangeEncoder& encoder, IntraModeContexts& contexts, TransformSize size,
                       const ModeCandidates& candidates, int mode);
// The bits encode_intra_mode spends on `mode` at the contexts' current state.
float intra_mode_bits(const IntraModeContexts& contexts, TransformSize size, const ModeCandidates& candidates,
                      int mode);

// What decode_chroma_mode reads (codec/decoder/intra_syntax_reader.h).
void encode_chroma_mode(RangeEncoder& encoder, CflContexts& cfl, IntraModeContexts& modes, int cfl_context,
                        const ModeCandidates& candidates, ChromaPlane plane, const ChromaMode& cb,
                        const ChromaMode& mode);
// Bits of the CfL flag, and of an alpha, at the contexts' current probabilities.
float cfl_flag_bits(const CflContexts& cfl, int cfl_context, bool set);
float cfl_alpha_bits(const CflContexts& cfl, ChromaPlane plane, int cb_alpha, int alpha);

void encode_transform_type(RangeEncoder& encoder, TransformTypeContexts& contexts, TransformSize size, int mode,
                           TransformType type);
// The bits encode_transform_type would write (0 when disabled).
float transform_type_bits(const TransformTypeContexts& contexts, TransformSize size, int mode, TransformType type);

}  // namespace svc::codec

namespace svc::codec::intra {

// A block's mode, prediction, residual levels and transform type.
struct BlockChoice {
  int mode = kDcMode;  // kCflMode for chroma from luma
  int cfl_alpha = 0;
  bool coded = false;
  TransformType transform_type = TransformType::kDctDct;  // DCT_DCT when not coded
  uint8_t prediction[kMaxTransformArea];
  int16_t levels[kMaxTransformArea];

  ChromaMode chroma_mode() const { return {mode, mode == kCflMode ? cfl_alpha : 0}; }
};

// The blocks of one luma macroblock as chosen, in coding order.
struct MacroblockChoice {
  LumaPartition partition = kSplit16x16;
  std::array<BlockChoice, 16> blocks;
};

// Writes a luma block's mode and levels, and marks it.
void write_block(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int x0, int y0,
                 TransformSize size, const BlockChoice& choice);
// Writes an 8x8 chroma block's mode (codec/cfl.h; `cb` is a Cr block's Cb block's mode)
// and levels, and marks it.
void write_chroma_block(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int x0, int y0,
                        ChromaPlane plane, const ChromaMode& cb, const BlockChoice& choice);

// Writes luma macroblock (mbx, mby): split flags and blocks.
void write_macroblock(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int mbx, int mby,
                      const MacroblockChoice& choice);

}  // namespace svc::codec::intra
