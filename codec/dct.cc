// Forward and inverse 8x8 DCT. The integer inverse is the contract of the bitstream:
// docs/codec.md defines it step by step and any change breaks decoding of existing files.
#include "codec/dct.h"

#include <array>
#include <cmath>
#include <numbers>

namespace svc::codec {
namespace {

// basis[u][x] = c(u) cos((2x+1) u pi / 16), c(0) = sqrt(1/8), c(u>0) = 1/2.
double basis(int u, int x) {
  const double c = u == 0 ? std::sqrt(0.125) : 0.5;
  return c * std::cos((2 * x + 1) * u * std::numbers::pi / 16.0);
}

struct DoubleBasis {
  double value[8][8];  // [u][x]
  DoubleBasis() {
    for (int u = 0; u < 8; ++u) {
      for (int x = 0; x < 8; ++x) value[u][x] = basis(u, x);
    }
  }
};
const DoubleBasis kDoubleBasis;

struct FloatBasis {
  float even[4][4];  // [k][x]: basis(2k, x)
  float odd[4][4];   // [k][x]: basis(2k+1, x)
  FloatBasis() {
    for (int k = 0; k < 4; ++k) {
      for (int x = 0; x < 4; ++x) {
        even[k][x] = static_cast<float>(basis(2 * k, x));
        odd[k][x] = static_cast<float>(basis(2 * k + 1, x));
      }
    }
  }
};
const FloatBasis kFloatBasis;

// Integer basis, 14 fractional bits: round(basis(u, x) * 16384), x < 4 (the other half
// follows from basis(u, 7 - x) = (-1)^u basis(u, x)). Spelled out because the decoder's
// output depends on every digit. Each column sums to 43284 in absolute value: with
// coefficients in [-2048, 2047] the row pass fits in 32 bits (|sum| < 2^27) and its
// output in 18 bits; the column pass accumulates in 64 bits.
constexpr int kIdctBasis[8][4] = {
    {5793, 5793, 5793, 5793},     // u = 0
    {8035, 6811, 4551, 1598},     // u = 1
    {7568, 3135, -3135, -7568},   // u = 2
    {6811, -1598, -8035, -4551},  // u = 3
    {5793, -5793, -5793, 5793},   // u = 4
    {4551, -8035, 1598, 6811},    // u = 5
    {3135, -7568, 7568, -3135},   // u = 6
    {1598, -4551, 6811, -8035},   // u = 7
};
constexpr int kRowShift = 9;      // row pass keeps 5 extra fractional bits
constexpr int kColumnShift = 19;  // 14 + 14 - 9

// One 1-D inverse over in[0], in[stride], ... writing out[0..7] with rounding shift,
// accumulating in Acc (int for rows, int64_t for columns).
template <typename Acc, typename In>
inline void idct_1d(const In* in, int stride, int shift, int* out) {
  const Acc f0 = in[0], f1 = in[stride], f2 = in[2 * stride], f3 = in[3 * stride];
  const Acc f4 = in[4 * stride], f5 = in[5 * stride], f6 = in[6 * stride], f7 = in[7 * stride];
  const Acc rounding = Acc{1} << (shift - 1);
  for (int x = 0; x < 4; ++x) {
    const Acc even = kIdctBasis[0][x] * f0 + kIdctBasis[2][x] * f2 + kIdctBasis[4][x] * f4 +
                     kIdctBasis[6][x] * f6 + rounding;
    const Acc odd = kIdctBasis[1][x] * f1 + kIdctBasis[3][x] * f3 + kIdctBasis[5][x] * f5 +
                    kIdctBasis[7][x] * f7;
    out[x] = static_cast<int>((even + odd) >> shift);
    out[7 - x] = static_cast<int>((even - odd) >> shift);
  }
}

}  // namespace

void forward_dct_8x8(const float* samples, float* coefficients) {
  float tmp[64];
  const auto& b = kFloatBasis;
  // Rows: tmp[y][u].
  for (int y = 0; y < 8; ++y) {
    const float* s = samples + 8 * y;
    float sum[4], diff[4];
    for (int x = 0; x < 4; ++x) {
      sum[x] = s[x] + s[7 - x];
      diff[x] = s[x] - s[7 - x];
    }
    for (int k = 0; k < 4; ++k) {
      tmp[8 * y + 2 * k] = b.even[k][0] * sum[0] + b.even[k][1] * sum[1] + b.even[k][2] * sum[2] +
                           b.even[k][3] * sum[3];
      tmp[8 * y + 2 * k + 1] = b.odd[k][0] * diff[0] + b.odd[k][1] * diff[1] +
                               b.odd[k][2] * diff[2] + b.odd[k][3] * diff[3];
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
      coefficients[8 * (2 * k) + u] = b.even[k][0] * sum[0] + b.even[k][1] * sum[1] +
                                      b.even[k][2] * sum[2] + b.even[k][3] * sum[3];
      coefficients[8 * (2 * k + 1) + u] = b.odd[k][0] * diff[0] + b.odd[k][1] * diff[1] +
                                          b.odd[k][2] * diff[2] + b.odd[k][3] * diff[3];
    }
  }
}

void forward_dct_8x8_reference(const double* samples, double* coefficients) {
  for (int v = 0; v < 8; ++v) {
    for (int u = 0; u < 8; ++u) {
      double sum = 0;
      for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) {
          sum += kDoubleBasis.value[v][y] * kDoubleBasis.value[u][x] * samples[8 * y + x];
        }
      }
      coefficients[8 * v + u] = sum;
    }
  }
}

void inverse_dct_8x8(const int16_t* coefficients, int16_t* samples) {
  bool dc_only = true;
  for (int i = 1; i < 64 && dc_only; ++i) dc_only = coefficients[i] == 0;
  if (dc_only) {
    // The general path below yields this same value at every position.
    const int row = (kIdctBasis[0][0] * coefficients[0] + (1 << (kRowShift - 1))) >> kRowShift;
    const int value = static_cast<int>(
        (int64_t{kIdctBasis[0][0]} * row + (int64_t{1} << (kColumnShift - 1))) >> kColumnShift);
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
    idct_1d<int>(row, 1, kRowShift, tmp + 8 * v);
  }
  for (int x = 0; x < 8; ++x) {
    int column[8];
    idct_1d<int64_t>(tmp + x, 8, kColumnShift, column);
    for (int y = 0; y < 8; ++y) samples[8 * y + x] = static_cast<int16_t>(column[y]);
  }
}

void inverse_dct_8x8_integer_reference(const int16_t* coefficients, int16_t* samples) {
  int tmp[64];
  for (int v = 0; v < 8; ++v) {
    for (int x = 0; x < 8; ++x) {
      int sum = 1 << (kRowShift - 1);
      for (int u = 0; u < 8; ++u) {
        const int b = x < 4 ? kIdctBasis[u][x] : ((u & 1) ? -kIdctBasis[u][7 - x] : kIdctBasis[u][7 - x]);
        sum += b * coefficients[8 * v + u];
      }
      tmp[8 * v + x] = sum >> kRowShift;
    }
  }
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      int64_t sum = int64_t{1} << (kColumnShift - 1);
      for (int v = 0; v < 8; ++v) {
        const int b = y < 4 ? kIdctBasis[v][y] : ((v & 1) ? -kIdctBasis[v][7 - y] : kIdctBasis[v][7 - y]);
        sum += int64_t{b} * tmp[8 * v + x];
      }
      samples[8 * y + x] = static_cast<int16_t>(sum >> kColumnShift);
    }
  }
}

void inverse_dct_8x8_reference(const double* coefficients, double* samples) {
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      double sum = 0;
      for (int v = 0; v < 8; ++v) {
        for (int u = 0; u < 8; ++u) {
          sum += kDoubleBasis.value[v][y] * kDoubleBasis.value[u][x] * coefficients[8 * v + u];
        }
      }
      samples[8 * y + x] = sum;
    }
  }
}

}  // namespace svc::codec
