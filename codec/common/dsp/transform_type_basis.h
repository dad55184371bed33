// SPDX-License-Identifier: BSD-2-Clause
// The integer matrices of the intra transform types other than DCT_DCT (docs/codec.md
// 7.2): HEVC's DCT matrix of each size and an integer DST-VII at the same scale,
// 64 sqrt(N) times orthonormal, so that either may serve either direction of a block.
// Part of the bitstream contract, shared by the kernels and the matrix-product
// definition in codec/common/dct.cc. The encoder's float forward bases are in
// codec/encoder/dsp/forward_type_basis.h.
#pragma once

#include <array>

#include "codec/common/dsp/dct_4_16_basis.h"

namespace svc::codec::dsp {

// DST-VII magnitudes by angle: kDstAngleTableN[j] = round(256 sqrt(N) sqrt(4 / (2N + 1))
// sin(pi j / (2N + 1))), j = 0..N: four times the DCT matrices' scale (2 more bits in
// the DST's pass), since rounded at that scale the DST's rows are orthogonal only to
// within 0.6 % at 16 points, against 0.1 % for HEVC's hand-tuned DCT.
inline constexpr int kDstExtraShift = 2;
inline constexpr std::array<int, 5> kDst4AngleTable = {0, 117, 219, 296, 336};
inline constexpr std::array<int, 9> kDst8AngleTable = {0, 65, 127, 185, 237, 280, 314, 338, 350};
inline constexpr std::array<int, 17> kDst16AngleTable = {0,   34,  67,  100, 133, 163, 193, 220, 246,
                                                         269, 290, 309, 324, 337, 346, 353, 356};

// Entry (k, n) of the N-point DST-VII, the integer sin(pi (2k + 1)(n + 1) / (2N + 1))
// scaled as above: the angle a = (2k + 1)(n + 1) mod 2(2N + 1) is negative past 2N + 1
// and folds to min(a, 2N + 1 - a).
template <size_t M>
constexpr int dst_entry(const std::array<int, M>& table, int k, int n) {
  const int points = static_cast<int>(M) - 1, period = 2 * points + 1;
  int angle = ((2 * k + 1) * (n + 1)) % (2 * period);
  int sign = 1;
  if (angle >= period) {
    angle -= period;
    sign = -1;
  }
  if (angle > points) angle = period - angle;
  return sign * table[static_cast<size_t>(angle)];
}

// One direction's N x N integer matrix, m[frequency][sample].
template <int N>
struct TypeMatrix {
  int m[N][N];
};

template <int N, size_t M>
constexpr TypeMatrix<N> dst_matrix(const std::array<int, M>& table) {
  TypeMatrix<N> matrix{};
  for (int k = 0; k < N; ++k) {
    for (int n = 0; n < N; ++n) matrix.m[k][n] = dst_entry(table, k, n);
  }
  return matrix;
}

template <int N>
constexpr TypeMatrix<N> dct_matrix() {
  TypeMatrix<N> matrix{};
  for (int k = 0; k < N; ++k) {
    for (int n = 0; n < N; ++n) matrix.m[k][n] = hevc_dct_entry(N, k, n);
  }
  return matrix;
}

inline constexpr TypeMatrix<4> kTypeDct4 = dct_matrix<4>();
inline constexpr TypeMatrix<8> kTypeDct8 = dct_matrix<8>();
inline constexpr TypeMatrix<16> kTypeDct16 = dct_matrix<16>();
inline constexpr TypeMatrix<4> kTypeDst4 = dst_matrix<4>(kDst4AngleTable);
inline constexpr TypeMatrix<8> kTypeDst8 = dst_matrix<8>(kDst8AngleTable);
inline constexpr TypeMatrix<16> kTypeDst16 = dst_matrix<16>(kDst16AngleTable);

// The two passes divide by (64 sqrt(N))^2 = 2^(12 + log2 N): 2^14 at 4x4 and 2^15 at
// 8x8 (orthonormal coefficients), 2^15 at 16x16 (coefficients half the orthonormal
// ones), as the size's DCT; a DST pass shifts kDstExtraShift more. Row outputs stay
// below 2^18 and sums below 2^30 for coefficients in [-2048, 2047]: 32-bit arithmetic.
constexpr int type_row_shift(bool dst) { return 4 + (dst ? kDstExtraShift : 0); }
// Rectangular blocks (docs/codec.md 5.5.3) shift 5.8 whatever their height.
constexpr int type_column_shift(int width, int height, bool dst) {
  return (width == 4 && height == 4 ? 10 : 11) + (dst ? kDstExtraShift : 0);
}

// The integer matrix of a direction: DST-VII when `dst`, else HEVC's DCT.
template <int N>
constexpr const TypeMatrix<N>& type_matrix(bool dst) {
  if constexpr (N == 4) return dst ? kTypeDst4 : kTypeDct4;
  if constexpr (N == 8) return dst ? kTypeDst8 : kTypeDct8;
  if constexpr (N == 16) return dst ? kTypeDst16 : kTypeDct16;
}

}  // namespace svc::codec::dsp
