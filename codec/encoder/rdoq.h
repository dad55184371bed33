// SPDX-License-Identifier: BSD-2-Clause
// Encoder only: rate-distortion optimized quantization (in the manner of HEVC's RDOQ).
// For each coefficient, in reverse scan order, it weighs the rounded level, one less,
// and zero by transform-domain squared error + lambda * bits, the bits from the block
// coder's contexts in their current state (unchanged); then it picks the end of block
// (possibly zeroing the tail) by the same cost. The bitstream does not depend on it: the
// result is a set of levels like any other.
//
// Threading: pure functions of their inputs. Errors: none (inputs are trusted encoder data).
#pragma once

#include <cstdint>

#include "codec/common/quant.h"
#include "codec/common/transform_type.h"
#include "codec/encoder/coefficient_writer.h"

namespace svc::codec {

// The levels of `coefficients` (a forward transform of quantizer.size, natural order)
// that minimize
// sum (coefficient - dequantized level)^2 + lambda * block_levels_bits(...), as far as the
// search sees, and never cost more by that measure than quantize_block's. `lambda` is
// in squared error per bit.
// Returns the number of non-zero levels. `levels_bits`, when not null, receives
// block_levels_bits of the levels chosen (the search has most often priced them already).
int rdoq_quantize_block(const Quantizer& quantizer, const float* coefficients, const BlockContextSet& contexts,
                        int coded_block_context, float lambda, int16_t* levels, float* levels_bits = nullptr);

// The cost that rdoq_quantize_block minimizes, for `levels`.
double quantization_rd_cost(const Quantizer& quantizer, const float* coefficients, const int16_t* levels,
                            const BlockContextSet& contexts, int coded_block_context, float lambda);

// Forward transform of `samples` (as transform_quantize_block, of type `type`) followed
// by either rdoq_quantize_block (rdoq true) or quantize_block; `levels_bits` as
// rdoq_quantize_block's.
int transform_quantize_block_rd(const Quantizer& quantizer, const int16_t* samples, bool rdoq,
                                const BlockContextSet& contexts, int coded_block_context, float lambda,
                                int16_t* levels, TransformType type = TransformType::kDctDct,
                                float* levels_bits = nullptr);

}  // namespace svc::codec
