// Forward and inverse 8x8 DCT. The integer inverse is the contract of the bitstream:
// docs/codec.md defines it step by step and any change breaks decoding of existing files.
#include "codec/dct.h"

#include <array>
#include <cmath>
#include <numbers>

#include "codec/dsp/dsp.h"
#include "codec/dsp/idct_basis.h"

namespace svc::codec {
namespace {

using dsp::kIdctBasis;
constexpr int kRowShift = dsp::kIdctRowShift;
constexpr int kColumnShift = dsp::kIdctColumnShift;

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

}  // namespace

void forward_dct_8x8(const float* samples, float* coefficients) {
  dsp::get_dsp().forward_dct_8x8(samples, coefficients);
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
  dsp::get_dsp().inverse_dct_8x8(coefficients, samples);
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
