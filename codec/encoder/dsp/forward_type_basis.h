// SPDX-License-Identifier: BSD-2-Clause
// The float bases and output scales of the intra transform types' forward transforms
// (docs/codec.md 5.5.2, 5.5.3), shared by the plain kernels and their variants so that all
// multiply by the same numbers: the integer matrices of
// codec/common/dsp/transform_type_basis.h scaled to orthonormal.
#pragma once

#include "codec/common/dsp/transform_type_basis.h"

namespace svc::codec::dsp {

// The forward transform's output scale (16x16: half the orthonormal scale, as its DCT;
// rectangular blocks, docs/codec.md 5.5.3: 8 / sqrt(W H) of it, which the passes' 2^15
// gives with the matrices of their sides: 1/sqrt(2) for 16x8 and 8x16, 1 for 16x4 and
// 4x16, sqrt(2) for 8x4 and 4x8).
constexpr float type_forward_scale(int width, int height) {
  if (width == height) return width == 16 ? 0.5f : 1.0f;
  const int area = width * height;
  return area == 128 ? 0.70710677f : area == 32 ? 1.41421354f : 1.0f;
}

// The forward transforms' bases in float, b[k][n] = matrix / (64 sqrt(N)) (DST: / (256
// sqrt(N))): the transpose of the integer inverse.
template <int N>
struct TypeFloatBasis {
  float b[N][N];
  explicit TypeFloatBasis(bool dst);
};
// The float basis of a direction (built once; thread-safe).
template <int N>
const TypeFloatBasis<N>& type_float_basis(bool dst);

}  // namespace svc::codec::dsp
