// SPDX-License-Identifier: BSD-2-Clause
// Internal to the dsp layer: the inverse_transform_add kernels (DspTable) as an inverse
// transform of the size followed by an add of the residual to the prediction, clipped to
// 8 bits. Each variant composes its own inverse with an add (the plain one here, or a
// SIMD one), so a table's add kernels are as fast as its inverses. Internal linkage, as
// files built for different instruction sets instantiate the same templates.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "codec/common/dsp/dsp.h"

namespace svc::codec::dsp {
namespace {

using InverseKernel = void (*)(const int16_t* coefficients, int16_t* samples);
using TypedInverseKernel = void (*)(int type, const int16_t* coefficients, int16_t* samples);
// dst = clip(prediction + residual, 0, 255) over a W x H block; `residual` holds W x H
// values row-major. `dst` may be `prediction` (same stride).
using AddKernel = void (*)(const int16_t* residual, const uint8_t* prediction, ptrdiff_t prediction_stride,
                           uint8_t* dst, ptrdiff_t dst_stride);

template <int W, int H>
void add_clipped_c(const int16_t* residual, const uint8_t* prediction, ptrdiff_t prediction_stride, uint8_t* dst,
                   ptrdiff_t dst_stride) {
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const int value = prediction[y * prediction_stride + x] + residual[W * y + x];
      dst[y * dst_stride + x] = static_cast<uint8_t>(std::clamp(value, 0, 255));
    }
  }
}

template <InverseKernel Inverse, AddKernel Add>
void inverse_add(const int16_t* coefficients, const uint8_t* prediction, ptrdiff_t prediction_stride, uint8_t* dst,
                 ptrdiff_t dst_stride) {
  alignas(32) int16_t residual[kMaxTransformArea];
  Inverse(coefficients, residual);
  Add(residual, prediction, prediction_stride, dst, dst_stride);
}

template <TypedInverseKernel Inverse, int Type>
void typed_inverse(const int16_t* coefficients, int16_t* samples) {
  Inverse(Type, coefficients, samples);
}

// The inverse_transform and inverse_transform_add entries of the W x H size from its
// typed inverse: types 1..3 for a square (whose DCT_DCT is a kernel of its own), 0..3 for
// a rectangular block.
template <int W, int H, TypedInverseKernel Inverse, AddKernel Add>
void set_typed_inverse(DspTable* table) {
  constexpr int size = size_index(transform_size_of(W, H));
  auto& inverse = table->inverse_transform[size];
  auto& add = table->inverse_transform_add[size];
  if constexpr (W != H) {
    inverse[0] = typed_inverse<Inverse, 0>;
    add[0] = inverse_add<typed_inverse<Inverse, 0>, Add>;
  }
  inverse[1] = typed_inverse<Inverse, 1>;
  inverse[2] = typed_inverse<Inverse, 2>;
  inverse[3] = typed_inverse<Inverse, 3>;
  add[1] = inverse_add<typed_inverse<Inverse, 1>, Add>;
  add[2] = inverse_add<typed_inverse<Inverse, 2>, Add>;
  add[3] = inverse_add<typed_inverse<Inverse, 3>, Add>;
}
// The DCT_DCT entries of a square size from its DCT.
template <int N, InverseKernel Inverse, AddKernel Add>
void set_dct_inverse(DspTable* table) {
  constexpr int size = size_index(transform_size_of(N, N));
  table->inverse_transform[size][0] = Inverse;
  table->inverse_transform_add[size][0] = inverse_add<Inverse, Add>;
}

}  // namespace
}  // namespace svc::codec::dsp
