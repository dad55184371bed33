// Plain quantization kernels (codec/quant.h defines the arithmetic).
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "codec/common/dsp/dsp_init.h"

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

void init_quant_c(DspTable* table) {
  table->quantize_8x8 = quantize_8x8_c;
  table->dequantize_8x8 = dequantize_8x8_c;
}

}  // namespace svc::codec::dsp
