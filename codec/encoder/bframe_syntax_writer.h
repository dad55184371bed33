// SPDX-License-Identifier: BSD-2-Clause
// B-face syntax writing and its bit estimates from the current adaptive probabilities:
// macroblock modes, partitions and directions, motion vector differences, predictor
// indices, epipolar lines and warp nodes (docs/codec.md 3.8), mirrored by
// codec/decoder/bframe_syntax_reader.h.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstdlib>

#include "codec/common/bframe_state.h"
#include "codec/encoder/bit_cost.h"
#include "codec/encoder/range_encoder.h"

namespace svc::codec::bframe {

// A magnitude of 1 .. 2^kMagnitudeClasses - 1 by class (docs/codec.md 3.8): the class
// in unary, the bit below the leading one, then the rest as bypass bits.
void encode_magnitude(RangeEncoder& encoder, MagnitudeBits& bits, unsigned magnitude);
float magnitude_bits(const MagnitudeBits& bits, unsigned magnitude);

// The bits of one vector difference component under one context, as tables over the
// class: for the motion search's many queries within one macroblock, where the contexts
// do not change.
class MvdCostTable {
 public:
  MvdCostTable() = default;
  MvdCostTable(const SyntaxContexts& c, int component, int context);
  float bits(int value) const {
    const auto magnitude = static_cast<unsigned>(std::abs(value));
    if (magnitude == 0) return zero_;
    const int k = std::min(static_cast<int>(std::bit_width(magnitude)) - 1, kMagnitudeClasses - 1);
    const int below = k > 0 ? static_cast<int>((magnitude >> (k - 1)) & 1) : 0;
    return class_[static_cast<size_t>(k)][static_cast<size_t>(below)];
  }

 private:
  float zero_ = 0;
  // [k][b]: the whole cost of a magnitude in class k whose bit below the leading one is
  // b, zero flag and sign included.
  std::array<std::array<float, 2>, kMagnitudeClasses> class_{};
};

float mode_bits(const FrameState& s, int mx, int my, MacroblockMode mode);

// Bits of the direction of an inter prediction (bidirectional, then backward flag; none
// with one reference), shared by a macroblock and each of its partitions.
float direction_bits(const FrameState& s, int mx, int my, MacroblockMode mode);

float partition_bits(const FrameState& s, int mx, int my, Partition partition);

// The partition element: split flag, then quad flag, then (two halves) vertical flag.
void encode_partition(RangeEncoder& encoder, FrameState& s, int mx, int my, Partition partition);

void encode_direction(RangeEncoder& encoder, FrameState& s, int mx, int my, MacroblockMode mode);

// A reference's epipolar lines (docs/codec.md 3.8): a, bx, by, each a signed value as
// an Exp-Golomb code in bypass bits.
void encode_epipolar_lines(RangeEncoder& encoder, const EpipolarLines& lines);

void encode_mvd_component(RangeEncoder& encoder, SyntaxContexts& c, int component, int context, int value);

// Which of `count` vector predictors a coded vector uses (nothing when count is 1).
float predictor_index_bits(const PredictorIndexBits& bits, int count, int index);
void encode_predictor_index(RangeEncoder& encoder, PredictorIndexBits& bits, int count, int index);

// A node difference component: zero flag, sign, then the magnitude by class.
float node_component_bits(const SyntaxContexts& c, int component, int kind, int value);

void encode_node_component(RangeEncoder& encoder, SyntaxContexts& c, int component, int kind, int value);

// Codes (encoder) the corner nodes of macroblock (mx, my) towards `reference` that the
// decoder does not know yet, in corner order, and marks them known.
void encode_missing_nodes(RangeEncoder& encoder, FrameState& s, int reference, int mx, int my,
                          MotionVector vector_predictor);

// Estimated bits of encode_missing_nodes, leaving the state unchanged.
float missing_nodes_bits(FrameState& s, int reference, int mx, int my, MotionVector vector_predictor);

}  // namespace svc::codec::bframe
