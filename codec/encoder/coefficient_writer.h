// SPDX-License-Identifier: BSD-2-Clause
// Writing and pricing of quantized transform blocks (docs/codec.md section 3.4), with the
// contexts of codec/common/coefficient_contexts.h; codec/decoder/coefficient_reader.h
// reads what it writes. The bit estimates run the same writer on a counting sink, so the
// two cannot drift apart.
//
// Threading: context sets are plain mutable data owned by one coder at a time.
#pragma once

#include <array>
#include <cstdint>

#include "codec/common/coefficient_contexts.h"
#include "codec/encoder/range_encoder.h"

namespace svc::codec {

// Codes the levels of a block of `size` (natural order, |level| <= kMaxLevel).
// coded_block_context in [0, kCodedBlockContexts) selects the coded-block flag's
// context, or kNoCodedBlockFlag (then the block must contain a non-zero level).
void encode_block_levels(RangeEncoder& encoder, BlockContextSet& contexts, const int16_t* levels,
                         int coded_block_context, TransformSize size = TransformSize::k8x8);

// The bits encode_block_levels would write, from the contexts' current
// probabilities (unchanged).
float block_levels_bits(const BlockContextSet& contexts, const int16_t* levels, int coded_block_context,
                        TransformSize size = TransformSize::k8x8);
// block_levels_bits of a block without levels: its coded-block flag (0), if coded.
float uncoded_block_bits(const BlockContextSet& contexts, int coded_block_context);

// For rate-distortion quantization: bits of the end-of-block position
// `last_scan` (0 .. the size's count - 1), the sum write_end_of_block forms,
// from per-class partial sums taken once for the many positions a search prices.
class EndOfBlockPricer {
 public:
  EndOfBlockPricer(const BlockContextSet& contexts, TransformSize size);
  float bits(int last_scan) const;

 private:
  const AdaptiveBit* extra_;  // eob_extra of the size
  // Per end-of-block class: its unary bits and terminating bit (if any), summed in order.
  std::array<float, kMaxEobClasses + 1> class_bits_{};
};

// Encoder only: bits of one non-zero magnitude with its sign at `position`, given
// the magnitudes coded before it and its `base_context` (significance context, or
// last_level_context at the end of block), without the significance flag.
float magnitude_bits(const BlockContextSet& contexts, const NeighbourMagnitudes& neighbours,
                     const PositionContext& position, int base_context, int magnitude);

// Exp-Golomb order 0 with bypass bits, for values below 2^17 - 1 (prefix <= 16).
void encode_exp_golomb_bypass(RangeEncoder& encoder, uint32_t value);

}  // namespace svc::codec
