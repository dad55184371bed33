// SPDX-License-Identifier: BSD-2-Clause
#include "codec/encoder/quantize.h"

#include <algorithm>

#include "codec/encoder/dsp/encoder_dsp.h"
#include "codec/encoder/forward_transform.h"

namespace svc::codec {

// The 8x8 kernels serve every size: areas of 64 and more as runs of 64 values, smaller
// ones (4x4, 8x4, 4x8) padded with zeros to 64, so that nothing past the block is read,
// written or counted.
namespace {

int quantize_with_rounding(const Quantizer& quantizer, const float* coefficients, float rounding_dc,
                           float rounding_ac, int16_t* levels) {
  const dsp::EncoderDspTable& dsp = dsp::get_encoder_dsp();
  const int area = transform_area(quantizer.size);
  if (area < 64) {
    float padded[64] = {};
    int16_t padded_levels[64];
    std::copy_n(coefficients, area, padded);
    const int count =
        dsp.quantize_8x8(padded, quantizer.inverse_step.data(), rounding_dc, rounding_ac, padded_levels);
    std::copy_n(padded_levels, area, levels);
    return count;
  }
  int count = 0;
  for (int i = 0; i < area; i += 64) {
    count += dsp.quantize_8x8(coefficients + i, quantizer.inverse_step.data() + i,
                              i == 0 ? rounding_dc : rounding_ac, rounding_ac, levels + i);
  }
  return count;
}

}  // namespace

int quantize_block(const Quantizer& quantizer, const float* coefficients, int16_t* levels) {
  return quantize_with_rounding(quantizer, coefficients, quantizer.rounding_dc, quantizer.rounding_ac, levels);
}

int quantize_block_nearest(const Quantizer& quantizer, const float* coefficients, int16_t* levels) {
  return quantize_with_rounding(quantizer, coefficients, 0.5f, 0.5f, levels);
}

int transform_quantize_block(const Quantizer& quantizer, const int16_t* samples, int16_t* levels,
                             TransformType type) {
  const int area = transform_area(quantizer.size);
  float input[kMaxTransformArea], coefficients[kMaxTransformArea];
  for (int i = 0; i < area; ++i) input[i] = samples[i];
  forward_transform(quantizer.size, type, input, coefficients);
  return quantize_block(quantizer, coefficients, levels);
}

}  // namespace svc::codec
