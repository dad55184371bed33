// SPDX-License-Identifier: BSD-2-Clause
// The plain dequantization kernel (codec/common/quant.h defines the arithmetic; the
// encoder's quantization is codec/encoder/dsp/quantize.cc).
#include <algorithm>
#include <cstdlib>

#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

void dequantize_8x8_c(const int16_t* levels, const int32_t* scale, int16_t* coefficients) {
  for (int i = 0; i < 64; ++i) {
    const int level = levels[i];
    // Every step is at least 128 / 256, so a level beyond 4096 saturates anyway; the
    // clamp keeps the product inside 32 bits for any int16 input.
    const int magnitude = (std::min(std::abs(level), 4096) * scale[i] + 128) >> 8;
    coefficients[i] = static_cast<int16_t>(level < 0 ? std::max(-magnitude, -2048) : std::min(magnitude, 2047));
  }
}

}  // namespace

void init_quant_c(DspTable* table) { table->dequantize_8x8 = dequantize_8x8_c; }

}  // namespace svc::codec::dsp
