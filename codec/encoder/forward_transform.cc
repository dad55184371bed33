// SPDX-License-Identifier: BSD-2-Clause
// The encoder's forward transforms through its kernel table, and the double-precision
// 8x8 reference the tests compare them with.
#include "codec/encoder/forward_transform.h"

#include <cmath>
#include <numbers>

#include "codec/common/dct.h"
#include "codec/encoder/dsp/encoder_dsp.h"

namespace svc::codec {
namespace {

// The typed kernels of a size (docs/codec.md 5.5.2, 5.5.3): types 1..3 for squares, whose
// DCT_DCT has kernels of its own, and 0..3 for rectangular sizes.
void forward_typed(const dsp::EncoderDspTable& dsp, TransformSize size, int type, const float* samples,
                   float* coefficients) {
  switch (size) {
    case TransformSize::k16x8: return dsp.forward_typed_16x8(type, samples, coefficients);
    case TransformSize::k8x16: return dsp.forward_typed_8x16(type, samples, coefficients);
    case TransformSize::k16x4: return dsp.forward_typed_16x4(type, samples, coefficients);
    case TransformSize::k4x16: return dsp.forward_typed_4x16(type, samples, coefficients);
    case TransformSize::k8x4: return dsp.forward_typed_8x4(type, samples, coefficients);
    case TransformSize::k4x8: return dsp.forward_typed_4x8(type, samples, coefficients);
    case TransformSize::k4x4: return dsp.forward_typed_4x4(type, samples, coefficients);
    case TransformSize::k16x16: return dsp.forward_typed_16x16(type, samples, coefficients);
    default: return dsp.forward_typed_8x8(type, samples, coefficients);
  }
}

}  // namespace

void forward_dct_8x8(const float* samples, float* coefficients) {
  dsp::get_encoder_dsp().forward_dct_8x8(samples, coefficients);
}

void forward_dct_8x8_reference(const double* samples, double* coefficients) {
  const DctBasis8x8& basis = dct_basis_8x8();
  for (int v = 0; v < 8; ++v) {
    for (int u = 0; u < 8; ++u) {
      double sum = 0;
      for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) {
          sum += basis[v][y] * basis[u][x] * samples[8 * y + x];
        }
      }
      coefficients[8 * v + u] = sum;
    }
  }
}

void forward_transform(TransformSize size, const float* samples, float* coefficients) {
  const dsp::EncoderDspTable& dsp = dsp::get_encoder_dsp();
  switch (size) {
    case TransformSize::k8x8: return dsp.forward_dct_8x8(samples, coefficients);
    case TransformSize::k4x4: return dsp.forward_dct_4x4(samples, coefficients);
    case TransformSize::k16x16: return dsp.forward_dct_16x16(samples, coefficients);
    default: return forward_typed(dsp, size, 0, samples, coefficients);
  }
}

void forward_transform(TransformSize size, TransformType type, const float* samples, float* coefficients) {
  if (type == TransformType::kDctDct) return forward_transform(size, samples, coefficients);
  forward_typed(dsp::get_encoder_dsp(), size, static_cast<int>(type), samples, coefficients);
}

}  // namespace svc::codec
