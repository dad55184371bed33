// SPDX-License-Identifier: BSD-2-Clause
// B-face syntax reading: macroblock partitions and directions, motion vector
// differences, predictor indices, epipolar lines and warp nodes (docs/codec.md 3.8).
// Errors: functions returning bool give false on syntax no encoder produces; none reads
// outside its input.
#pragma once

#include <cstdint>

#include "codec/common/bframe_state.h"
#include "codec/decoder/range_decoder.h"

namespace svc::codec::bframe {

// A magnitude of 1 .. 2^kMagnitudeClasses - 1 by class (docs/codec.md 3.8): the class
// in unary, the bit below the leading one, then the rest as bypass bits.
unsigned decode_magnitude(RangeDecoder& decoder, MagnitudeBits& bits);

// The partition element: split flag, then quad flag, then (two halves) vertical flag.
Partition decode_partition(RangeDecoder& decoder, FrameState& s, int mx, int my);

// The direction of an inter prediction (bidirectional, then backward flag; none with one
// reference).
MacroblockMode decode_direction(RangeDecoder& decoder, FrameState& s, int mx, int my);

// A reference's epipolar lines (docs/codec.md 3.8): a, bx, by, each a signed value as
// an Exp-Golomb code in bypass bits. Refuses magnitudes above kMaxEpipolarCoefficient.
bool decode_epipolar_lines(RangeDecoder& decoder, EpipolarLines* lines);

// Which of `count` vector predictors a coded vector uses (0 when count is 1): a bit for
// index > 0, then with three predictors a bit for index 2. `bits` is
// SyntaxContexts::predictor_index or skip_predictor_index.
int decode_predictor_index(RangeDecoder& decoder, PredictorIndexBits& bits, int count);

int decode_mvd_component(RangeDecoder& decoder, SyntaxContexts& c, int component, int context);

// A node difference component: zero flag, sign, then the magnitude by class.
int decode_node_component(RangeDecoder& decoder, SyntaxContexts& c, int component, int kind);

// Decodes the missing corner nodes of macroblock (mx, my); false on a syntax error or a
// node beyond the range.
bool decode_missing_nodes(RangeDecoder& decoder, FrameState& s, int reference, int mx, int my,
                          MotionVector vector_predictor);

}  // namespace svc::codec::bframe
