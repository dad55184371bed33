// SPDX-License-Identifier: BSD-2-Clause
// The plain quantization kernel (codec/encoder/quantize.h and codec/common/quant.h define
// the arithmetic).
#include <cmath>

#include "codec/encoder/dsp/encoder_dsp_init.h"

namespace svc::codec::dsp {
namespace {

constexpr int kMaxLevel = 4095;

int quantize_8x8_c(const float* coefficients, const float* inverse_step, float rounding_dc, float rounding_ac,
                   int16_t* levels) {
  int nonzero = 0;
  for (int i = 0; i < 64; ++i) {
    const float rounding = i == 0 ? rounding_dc : rounding_ac;
    const float magnitude = std::fabs(coefficients[i]) * inverse_step[i] + rounding;
    int level = magnitude >= static_cast<float>(kMaxLevel) ? kMaxLevel : static_cast<int>(magnitude);
    if (coefficients[i] < 0) level = -level;
    levels[i] = static_cast<int16_t>(level);
    nonzero += level != 0;
  }
  return nonzero;
}

}  // namespace

void init_quantize_c(EncoderDspTable* table) { table->quantize_8x8 = quantize_8x8_c; }

}  // namespace svc::codec::dsp
