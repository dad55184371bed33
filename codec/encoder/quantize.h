// SPDX-License-Identifier: BSD-2-Clause
// The encoder's quantization of transform coefficients to levels (the quantizers and
// the exact dequantization that encoder and decoder share are codec/common/quant.h):
// float arithmetic with the quantizer's rate-distortion rounding offsets, through the
// encoder's kernel table (codec/encoder/dsp/encoder_dsp.h). Pure and thread-safe.
#pragma once

#include <cstdint>

#include "codec/common/quant.h"
#include "codec/common/transform_type.h"

namespace svc::codec {

// Quantizes DCT coefficients (natural order, quantizer.size) to levels in
// [-kMaxLevel, kMaxLevel]. Returns the number of non-zero levels.
int quantize_block(const Quantizer& quantizer, const float* coefficients, int16_t* levels);
// The same with rounding 0.5 for every level, whatever the quantizer's (RDOQ's start).
int quantize_block_nearest(const Quantizer& quantizer, const float* coefficients, int16_t* levels);

// Forward transform (the DCT, or an intra transform type) + quantization of one block
// of samples (intra: pixel - 128; non-intra: residual). Returns the number of non-zero levels.
int transform_quantize_block(const Quantizer& quantizer, const int16_t* samples, int16_t* levels,
                             TransformType type = TransformType::kDctDct);

}  // namespace svc::codec
