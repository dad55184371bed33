// SPDX-License-Identifier: BSD-2-Clause
// AVX2 16x16 forward DCT: each pass computes a whole row of 16 outputs in two registers
// (lanes over the frequency u), with every sum in the plain kernel's order and no fused
// multiply-add, so it rounds exactly as the plain and SSE4.1 code do. The 4x4 stays
// SSE4.1: at eight lanes it would gain little.
#include <immintrin.h>

#include "codec/common/dsp/x86/target.h"
#include "codec/encoder/dsp/encoder_dsp_init.h"
#include "codec/encoder/dsp/fdct_4_16_basis.h"
#include "codec/encoder/dsp/x86/transposed_basis.h"

SVC_TARGET_BEGIN("avx2")

namespace svc::codec::dsp {
namespace {

constexpr int kN = 16;

void forward_dct_16x16_avx2(const float* samples, float* coefficients) {
  static const TransposedBasis<kN> transposed(kForwardDct16Basis);
  alignas(32) float tmp[kN * kN];
  for (int y = 0; y < kN; ++y) {
    __m256 low = _mm256_setzero_ps(), high = _mm256_setzero_ps();
    for (int x = 0; x < kN; ++x) {
      const __m256 sample = _mm256_set1_ps(samples[kN * y + x]);
      low = _mm256_add_ps(low, _mm256_mul_ps(_mm256_load_ps(&transposed.bt[x][0]), sample));
      high = _mm256_add_ps(high, _mm256_mul_ps(_mm256_load_ps(&transposed.bt[x][8]), sample));
    }
    _mm256_store_ps(tmp + kN * y, low);
    _mm256_store_ps(tmp + kN * y + 8, high);
  }
  const __m256 half = _mm256_set1_ps(0.5f);
  for (int v = 0; v < kN; ++v) {
    __m256 low = _mm256_setzero_ps(), high = _mm256_setzero_ps();
    for (int y = 0; y < kN; ++y) {
      const __m256 weight = _mm256_set1_ps(kForwardDct16Basis.b[v][y]);
      low = _mm256_add_ps(low, _mm256_mul_ps(weight, _mm256_load_ps(tmp + kN * y)));
      high = _mm256_add_ps(high, _mm256_mul_ps(weight, _mm256_load_ps(tmp + kN * y + 8)));
    }
    _mm256_storeu_ps(coefficients + kN * v, _mm256_mul_ps(low, half));
    _mm256_storeu_ps(coefficients + kN * v + 8, _mm256_mul_ps(high, half));
  }
}

}  // namespace

void init_forward_transform_4_16_avx2(EncoderDspTable* table) { table->forward_dct_16x16 = forward_dct_16x16_avx2; }

}  // namespace svc::codec::dsp

SVC_TARGET_END
