// SPDX-License-Identifier: BSD-2-Clause
// The plain 8x8 float forward DCT: the separable transform with an even/odd butterfly
// per 1-D pass (the integer inverse is the shared table's, codec/common/dsp/transform.cc).
#include <cmath>
#include <numbers>

#include "codec/encoder/dsp/encoder_dsp_init.h"
#include "codec/encoder/dsp/fdct_basis.h"

namespace svc::codec::dsp {

ForwardDctBasis::ForwardDctBasis() {
  // basis[u][x] = c(u) cos((2x+1) u pi / 16), c(0) = sqrt(1/8), c(u>0) = 1/2.
  auto basis = [](int u, int x) {
    const double c = u == 0 ? std::sqrt(0.125) : 0.5;
    return c * std::cos((2 * x + 1) * u * std::numbers::pi / 16.0);
  };
  for (int k = 0; k < 4; ++k) {
    for (int x = 0; x < 4; ++x) {
      even[k][x] = static_cast<float>(basis(2 * k, x));
      odd[k][x] = static_cast<float>(basis(2 * k + 1, x));
    }
  }
}
const ForwardDctBasis kForwardDctBasis;

namespace {

void forward_dct_8x8_c(const float* samples, float* coefficients) {
  float tmp[64];
  const auto& b = kForwardDctBasis;
  // Rows: tmp[y][u].
  for (int y = 0; y < 8; ++y) {
    const float* s = samples + 8 * y;
    float sum[4], diff[4];
    for (int x = 0; x < 4; ++x) {
      sum[x] = s[x] + s[7 - x];
      diff[x] = s[x] - s[7 - x];
    }
    for (int k = 0; k < 4; ++k) {
      tmp[8 * y + 2 * k] =
          b.even[k][0] * sum[0] + b.even[k][1] * sum[1] + b.even[k][2] * sum[2] + b.even[k][3] * sum[3];
      tmp[8 * y + 2 * k + 1] =
          b.odd[k][0] * diff[0] + b.odd[k][1] * diff[1] + b.odd[k][2] * diff[2] + b.odd[k][3] * diff[3];
    }
  }
  // Columns.
  for (int u = 0; u < 8; ++u) {
    float sum[4], diff[4];
    for (int y = 0; y < 4; ++y) {
      sum[y] = tmp[8 * y + u] + tmp[8 * (7 - y) + u];
      diff[y] = tmp[8 * y + u] - tmp[8 * (7 - y) + u];
    }
    for (int k = 0; k < 4; ++k) {
      coefficients[8 * (2 * k) + u] =
          b.even[k][0] * sum[0] + b.even[k][1] * sum[1] + b.even[k][2] * sum[2] + b.even[k][3] * sum[3];
      coefficients[8 * (2 * k + 1) + u] =
          b.odd[k][0] * diff[0] + b.odd[k][1] * diff[1] + b.odd[k][2] * diff[2] + b.odd[k][3] * diff[3];
    }
  }
}

}  // namespace

void init_forward_transform_c(EncoderDspTable* table) { table->forward_dct_8x8 = forward_dct_8x8_c; }

}  // namespace svc::codec::dsp
