// SPDX-License-Identifier: BSD-2-Clause
// The integer inverse DCTs of 4x4 and 16x16 blocks: HEVC's integer DCT matrices and the
// shifts of their two passes, part of the bitstream contract (docs/codec.md section 5.5),
// shared by the kernels and the matrix-product definitions in codec/common/dct.cc. The
// encoder's float forward bases are in codec/encoder/dsp/fdct_4_16_basis.h.
#pragma once

#include <array>
#include <cstddef>

namespace svc::codec::dsp {

// HEVC's 16-point DCT entries by angle: K16[k][n] = s T[a] with k (2n + 1) = a' (mod 64),
// a' folded into 0..16 (a = a' or 64 - a'; then 32 - a with sign s = -1 when above 16).
// T[0] = 64 serves the DC row (k = 0); every digit matters to the decoder.
inline constexpr std::array<int, 16> kDctAngleTable = {64, 90, 89, 87, 83, 80, 75, 70,
                                                       64, 57, 50, 43, 36, 25, 18, 9};

// Entry (k, n) of HEVC's N-point matrix, N = 4, 8 or 16 (the N-point matrix is the
// 16-point one at angles scaled by 16 / N).
constexpr int hevc_dct_entry(int points, int k, int n) {
  int angle = (k * (2 * n + 1) * (16 / points)) % 64;
  if (angle > 32) angle = 64 - angle;
  int sign = 1;
  if (angle > 16) {
    angle = 32 - angle;
    sign = -1;
  }
  return angle == 16 ? 0 : sign * kDctAngleTable[static_cast<size_t>(angle)];
}

template <int N>
struct HevcDctMatrix {
  int m[N][N];  // [frequency][sample]
  constexpr HevcDctMatrix() : m{} {
    for (int k = 0; k < N; ++k) {
      for (int n = 0; n < N; ++n) m[k][n] = hevc_dct_entry(N, k, n);
    }
  }
};
inline constexpr HevcDctMatrix<4> kDct4Matrix;
inline constexpr HevcDctMatrix<16> kDct16Matrix;

// Pass shifts: the entries are 64 sqrt(N) times the orthonormal basis, so the two passes
// together divide by 2^14 (4x4, orthonormal coefficients) or 2^15 (16x16, whose
// coefficients are half the orthonormal ones). The row pass keeps 32-bit intermediates
// with fractional bits: |row output| < 2^19 for coefficients in [-2048, 2047], and the
// column sums stay below 2^31. The output saturates to 16 bits (reached only by extreme
// 16x16 coefficients no residual produces).
inline constexpr int kIdct4RowShift = 4;
inline constexpr int kIdct4ColumnShift = 10;
inline constexpr int kIdct16RowShift = 4;
inline constexpr int kIdct16ColumnShift = 11;

}  // namespace svc::codec::dsp
