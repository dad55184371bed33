// SPDX-License-Identifier: BSD-2-Clause
// The NEON integer inverse of a separable W x H transform (W samples a row) given its two integer
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
template <int W, int H>
void inverse_by_matrices(const int (&rows)[W][W], int row_shift, const int (&columns)[H][H], int column_shift,
                         const int16_t* coefficients, int16_t* samples) {
  int32_t tmp[W * H];
  const int32x4_t row_round = vdupq_n_s32(1 << (row_shift - 1)), row_bits = vdupq_n_s32(-row_shift);
  for (int v = 0; v < H; ++v) {
    const int16_t* in = coefficients + W * v;
    for (int x = 0; x < W; x += 4) {
      int32x4_t sum = row_round;
      for (int u = 0; u < W; ++u) {
        if (in[u] != 0) sum = vmlaq_n_s32(sum, vld1q_s32(&rows[u][x]), in[u]);
      }
      vst1q_s32(tmp + W * v + x, vshlq_s32(sum, row_bits));  // a negative count shifts right
    }
  }
  const int32x4_t column_round = vdupq_n_s32(1 << (column_shift - 1)), column_bits = vdupq_n_s32(-column_shift);
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; x += 4) {
      int32x4_t sum = column_round;
      for (int v = 0; v < H; ++v) sum = vmlaq_n_s32(sum, vld1q_s32(tmp + W * v + x), columns[v][y]);
      vst1_s16(samples + W * y + x, vqmovn_s32(vshlq_s32(sum, column_bits)));
    }
  }
}

}  // namespace
}  // namespace svc::codec::dsp
