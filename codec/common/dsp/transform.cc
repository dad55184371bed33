// Plain 8x8 DCT kernels: the separable float forward transform (even/odd butterfly per
// 1-D pass) and the integer inverse with its zero-row and DC-only shortcuts. The inverse
// is the bitstream's contract: its output must equal codec/dct.cc's matrix product.
#include <cmath>
#include <numbers>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/fdct_basis.h"
#include "codec/common/dsp/idct_basis.h"

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

// One 1-D inverse over in[0], in[stride], ... writing out[0..7] with rounding shift,
// accumulating in Acc (int for rows, int64_t for columns).
template <typename Acc, typename In>
inline void idct_1d(const In* in, int stride, int shift, int* out) {
  const Acc f0 = in[0], f1 = in[stride], f2 = in[2 * stride], f3 = in[3 * stride];
  const Acc f4 = in[4 * stride], f5 = in[5 * stride], f6 = in[6 * stride], f7 = in[7 * stride];
  const Acc rounding = Acc{1} << (shift - 1);
  for (int x = 0; x < 4; ++x) {
    const Acc even =
        kIdctBasis[0][x] * f0 + kIdctBasis[2][x] * f2 + kIdctBasis[4][x] * f4 + kIdctBasis[6][x] * f6 + rounding;
    const Acc odd = kIdctBasis[1][x] * f1 + kIdctBasis[3][x] * f3 + kIdctBasis[5][x] * f5 + kIdctBasis[7][x] * f7;
    out[x] = static_cast<int>((even + odd) >> shift);
    out[7 - x] = static_cast<int>((even - odd) >> shift);
  }
}

void inverse_dct_8x8_c(const int16_t* coefficients, int16_t* samples) {
  bool dc_only = true;
  for (int i = 1; i < 64 && dc_only; ++i) dc_only = coefficients[i] == 0;
  if (dc_only) {
    // The general path below yields this same value at every position.
    const int row = (kIdctBasis[0][0] * coefficients[0] + (1 << (kIdctRowShift - 1))) >> kIdctRowShift;
    const int value = static_cast<int>((int64_t{kIdctBasis[0][0]} * row + (int64_t{1} << (kIdctColumnShift - 1))) >>
                                       kIdctColumnShift);
    for (int i = 0; i < 64; ++i) samples[i] = static_cast<int16_t>(value);
    return;
  }
  int tmp[64];
  for (int v = 0; v < 8; ++v) {
    const int16_t* row = coefficients + 8 * v;
    bool zero = true;
    for (int u = 0; u < 8 && zero; ++u) zero = row[u] == 0;
    if (zero) {
      for (int x = 0; x < 8; ++x) tmp[8 * v + x] = 0;  // what idct_1d gives for zeros
      continue;
    }
    idct_1d<int>(row, 1, kIdctRowShift, tmp + 8 * v);
  }
  for (int x = 0; x < 8; ++x) {
    int column[8];
    idct_1d<int64_t>(tmp + x, 8, kIdctColumnShift, column);
    for (int y = 0; y < 8; ++y) samples[8 * y + x] = static_cast<int16_t>(column[y]);
  }
}

}  // namespace

void init_transform_c(DspTable* table) {
  table->forward_dct_8x8 = forward_dct_8x8_c;
  table->inverse_dct_8x8 = inverse_dct_8x8_c;
}

}  // namespace svc::codec::dsp
