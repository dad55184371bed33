// The NEON integer inverse of a separable N x N transform given its two integer
// matrices, shared by the 4x4/16x16 DCT and the transform-type kernels (internal
// linkage). Four outputs of a row at a time (lanes over the sample x), every 32-bit sum
// the plain kernel's, which never overflows, so the results agree bit for bit. The row
// pass skips zero coefficients, which add nothing; the saturating narrow is the plain
// kernel's clamp to 16 bits.
#pragma once

#include <arm_neon.h>

#include <cstdint>

namespace svc::codec::dsp {
namespace {

// rows[u][x] and columns[v][y]: the matrices of the horizontal and vertical passes.
template <int N>
void inverse_by_matrices(const int (&rows)[N][N], int row_shift, const int (&columns)[N][N], int column_shift,
                         const int16_t* coefficients, int16_t* samples) {
  int32_t tmp[N * N];
  const int32x4_t row_round = vdupq_n_s32(1 << (row_shift - 1)), row_bits = vdupq_n_s32(-row_shift);
  for (int v = 0; v < N; ++v) {
    const int16_t* in = coefficients + N * v;
    for (int x = 0; x < N; x += 4) {
      int32x4_t sum = row_round;
      for (int u = 0; u < N; ++u) {
        if (in[u] != 0) sum = vmlaq_n_s32(sum, vld1q_s32(&rows[u][x]), in[u]);
      }
      vst1q_s32(tmp + N * v + x, vshlq_s32(sum, row_bits));  // a negative count shifts right
    }
  }
  const int32x4_t column_round = vdupq_n_s32(1 << (column_shift - 1)), column_bits = vdupq_n_s32(-column_shift);
  for (int y = 0; y < N; ++y) {
    for (int x = 0; x < N; x += 4) {
      int32x4_t sum = column_round;
      for (int v = 0; v < N; ++v) sum = vmlaq_n_s32(sum, vld1q_s32(tmp + N * v + x), columns[v][y]);
      vst1_s16(samples + N * y + x, vqmovn_s32(vshlq_s32(sum, column_bits)));
    }
  }
}

}  // namespace
}  // namespace svc::codec::dsp
