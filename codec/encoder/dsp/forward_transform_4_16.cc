// SPDX-License-Identifier: BSD-2-Clause
// Plain 4x4 and 16x16 float forward DCTs: separable transforms with HEVC's integer
// matrices scaled to (near) orthonormal (for 16x16, half that scale so that
// coefficients fit 12 bits), the transposes of the shared table's integer inverses.
#include <cmath>

#include "codec/encoder/dsp/encoder_dsp_init.h"
#include "codec/encoder/dsp/fdct_4_16_basis.h"

namespace svc::codec::dsp {

// The integer matrix / (64 sqrt(N)): HEVC's near-orthonormal approximation of the DCT,
// so that the forward transform is the transpose of the integer inverse.
template <int N>
ForwardDctFloatBasis<N>::ForwardDctFloatBasis() {
  const double scale = 64.0 * std::sqrt(static_cast<double>(N));
  for (int k = 0; k < N; ++k) {
    for (int n = 0; n < N; ++n) b[k][n] = static_cast<float>(hevc_dct_entry(N, k, n) / scale);
  }
}
template struct ForwardDctFloatBasis<4>;
template struct ForwardDctFloatBasis<16>;
const ForwardDctFloatBasis<4> kForwardDct4Basis;
const ForwardDctFloatBasis<16> kForwardDct16Basis;

namespace {

// Rows then columns; each sum accumulates in increasing sample order (the SIMD variants
// keep this order so that every float rounds alike). `scale` is a power of two (exact).
template <int N>
void forward_dct(const ForwardDctFloatBasis<N>& basis, float scale, const float* samples, float* coefficients) {
  float tmp[N * N];
  for (int y = 0; y < N; ++y) {
    for (int u = 0; u < N; ++u) {
      float sum = 0;
      for (int x = 0; x < N; ++x) sum += basis.b[u][x] * samples[N * y + x];
      tmp[N * y + u] = sum;
    }
  }
  for (int u = 0; u < N; ++u) {
    for (int v = 0; v < N; ++v) {
      float sum = 0;
      for (int y = 0; y < N; ++y) sum += basis.b[v][y] * tmp[N * y + u];
      coefficients[N * v + u] = sum * scale;
    }
  }
}

}  // namespace

void forward_dct_4x4_c(const float* samples, float* coefficients) {
  forward_dct(kForwardDct4Basis, 1.0f, samples, coefficients);
}
void forward_dct_16x16_c(const float* samples, float* coefficients) {
  forward_dct(kForwardDct16Basis, 0.5f, samples, coefficients);
}

void init_forward_transform_4_16_c(EncoderDspTable* table) {
  table->forward_dct_4x4 = forward_dct_4x4_c;
  table->forward_dct_16x16 = forward_dct_16x16_c;
}

}  // namespace svc::codec::dsp
