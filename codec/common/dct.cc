// SPDX-License-Identifier: BSD-2-Clause
// The inverse transforms through the kernel table and their definitional references.
// The integer inverses are the contract of the bitstream:
// docs/codec.md defines it step by step and any change breaks decoding of existing files.
#include "codec/common/dct.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "codec/common/dsp/dct_4_16_basis.h"
#include "codec/common/dsp/dsp.h"
#include "codec/common/dsp/idct_basis.h"
#include "codec/common/dsp/transform_type_basis.h"

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

}  // namespace

const DctBasis8x8& dct_basis_8x8() {
  static const auto table = [] {
    struct Table {
      double value[8][8];
    } t{};
    for (int u = 0; u < 8; ++u) {
      for (int x = 0; x < 8; ++x) t.value[u][x] = basis(u, x);
    }
    return t;
  }();
  return table.value;
}

void inverse_dct_8x8(const int16_t* coefficients, int16_t* samples) {
  inverse_transform(TransformSize::k8x8, TransformType::kDctDct, coefficients, samples);
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
  const DctBasis8x8& basis = dct_basis_8x8();
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      double sum = 0;
      for (int v = 0; v < 8; ++v) {
        for (int u = 0; u < 8; ++u) {
          sum += basis[v][y] * basis[u][x] * coefficients[8 * v + u];
        }
      }
      samples[8 * y + x] = sum;
    }
  }
}

namespace {

// Entry (k, n) of a direction's integer matrix at `points` = 4, 8 or 16.
int type_matrix_entry(int points, bool dst, int k, int n) {
  if (points == 4) return dsp::type_matrix<4>(dst).m[k][n];
  if (points == 8) return dsp::type_matrix<8>(dst).m[k][n];
  return dsp::type_matrix<16>(dst).m[k][n];
}

}  // namespace

void inverse_transform(TransformSize size, const int16_t* coefficients, int16_t* samples) {
  inverse_transform(size, TransformType::kDctDct, coefficients, samples);
}

void inverse_transform_integer_reference(TransformSize size, const int16_t* coefficients, int16_t* samples) {
  if (is_rectangular(size))
    return inverse_transform_integer_reference(size, TransformType::kDctDct, coefficients, samples);
  if (size == TransformSize::k8x8) {
    inverse_dct_8x8_integer_reference(coefficients, samples);
    return;
  }
  const bool small = size == TransformSize::k4x4;
  const int n = transform_width(size);
  const int row_shift = small ? dsp::kIdct4RowShift : dsp::kIdct16RowShift;
  const int column_shift = small ? dsp::kIdct4ColumnShift : dsp::kIdct16ColumnShift;
  auto matrix = [&](int k, int x) { return small ? dsp::kDct4Matrix.m[k][x] : dsp::kDct16Matrix.m[k][x]; };
  int tmp[kMaxTransformArea];
  for (int v = 0; v < n; ++v) {
    for (int x = 0; x < n; ++x) {
      int sum = 1 << (row_shift - 1);
      for (int u = 0; u < n; ++u) sum += matrix(u, x) * coefficients[n * v + u];
      tmp[n * v + x] = sum >> row_shift;
    }
  }
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      int sum = 1 << (column_shift - 1);
      for (int v = 0; v < n; ++v) sum += matrix(v, y) * tmp[n * v + x];
      samples[n * y + x] = static_cast<int16_t>(std::clamp(sum >> column_shift, -32768, 32767));
    }
  }
}

void inverse_transform_reference(TransformSize size, const double* coefficients, double* samples) {
  if (size == TransformSize::k8x8) {
    inverse_dct_8x8_reference(coefficients, samples);
    return;
  }
  const int w = transform_width(size), h = transform_height(size);
  const double scale = size == TransformSize::k16x16 ? 2.0
                       : is_rectangular(size)        ? std::pow(std::sqrt(2.0), -rectangular_scale_log_sqrt2(size))
                                                     : 1.0;
  auto basis = [](int n, int k, int x) {
    return dsp::hevc_dct_entry(n, k, x) / (64.0 * std::sqrt(static_cast<double>(n)));
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      double sum = 0;
      for (int v = 0; v < h; ++v) {
        for (int u = 0; u < w; ++u) sum += basis(h, v, y) * basis(w, u, x) * coefficients[w * v + u];
      }
      samples[w * y + x] = scale * sum;
    }
  }
}

void inverse_transform(TransformSize size, TransformType type, const int16_t* coefficients, int16_t* samples) {
  dsp::get_dsp().inverse_transform[size_index(size)][static_cast<int>(type)](coefficients, samples);
}

void inverse_transform_integer_reference(TransformSize size, TransformType type, const int16_t* coefficients,
                                         int16_t* samples) {
  if (type == TransformType::kDctDct && !is_rectangular(size)) {
    inverse_transform_integer_reference(size, coefficients, samples);
    return;
  }
  const int w = transform_width(size), h = transform_height(size);
  const bool rows_dst = horizontal_dst(type), columns_dst = vertical_dst(type);
  const int row_shift = dsp::type_row_shift(rows_dst), column_shift = dsp::type_column_shift(w, h, columns_dst);
  int tmp[kMaxTransformArea];
  for (int v = 0; v < h; ++v) {
    for (int x = 0; x < w; ++x) {
      int sum = 1 << (row_shift - 1);
      for (int u = 0; u < w; ++u) sum += type_matrix_entry(w, rows_dst, u, x) * coefficients[w * v + u];
      tmp[w * v + x] = sum >> row_shift;
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      int sum = 1 << (column_shift - 1);
      for (int v = 0; v < h; ++v) sum += type_matrix_entry(h, columns_dst, v, y) * tmp[w * v + x];
      samples[w * y + x] = static_cast<int16_t>(std::clamp(sum >> column_shift, -32768, 32767));
    }
  }
}

}  // namespace svc::codec
