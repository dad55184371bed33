// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 4x4 and 16x16 float forward DCTs: four outputs of a row at once (lanes over the
// frequency u) with every sum in the plain kernel's order, so they round exactly as the
// plain code does (no fused multiply-add).
#include <smmintrin.h>

#include "codec/common/dsp/x86/target.h"
#include "codec/encoder/dsp/encoder_dsp_init.h"
#include "codec/encoder/dsp/fdct_4_16_basis.h"
#include "codec/encoder/dsp/x86/transposed_basis.h"

SVC_TARGET_BEGIN("sse4.1")

namespace svc::codec::dsp {
namespace {

template <int N>
void forward_dct(const ForwardDctFloatBasis<N>& basis, const TransposedBasis<N>& transposed, float scale,
                 const float* samples, float* coefficients) {
  alignas(16) float tmp[N * N];
  for (int y = 0; y < N; ++y) {
    for (int u = 0; u < N; u += 4) {
      __m128 sum = _mm_setzero_ps();
      for (int x = 0; x < N; ++x) {
        sum = _mm_add_ps(sum, _mm_mul_ps(_mm_load_ps(&transposed.bt[x][u]), _mm_set1_ps(samples[N * y + x])));
      }
      _mm_store_ps(tmp + N * y + u, sum);
    }
  }
  const __m128 factor = _mm_set1_ps(scale);
  for (int v = 0; v < N; ++v) {
    for (int u = 0; u < N; u += 4) {
      __m128 sum = _mm_setzero_ps();
      for (int y = 0; y < N; ++y) {
        sum = _mm_add_ps(sum, _mm_mul_ps(_mm_set1_ps(basis.b[v][y]), _mm_load_ps(tmp + N * y + u)));
      }
      _mm_storeu_ps(coefficients + N * v + u, _mm_mul_ps(sum, factor));
    }
  }
}

void forward_dct_4x4_sse41(const float* samples, float* coefficients) {
  static const TransposedBasis<4> transposed(kForwardDct4Basis);
  forward_dct(kForwardDct4Basis, transposed, 1.0f, samples, coefficients);
}

void forward_dct_16x16_sse41(const float* samples, float* coefficients) {
  static const TransposedBasis<16> transposed(kForwardDct16Basis);
  forward_dct(kForwardDct16Basis, transposed, 0.5f, samples, coefficients);
}

}  // namespace

void init_forward_transform_4_16_sse41(EncoderDspTable* table) {
  table->forward_dct_4x4 = forward_dct_4x4_sse41;
  table->forward_dct_16x16 = forward_dct_16x16_sse41;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
