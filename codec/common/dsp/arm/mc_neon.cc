// SPDX-License-Identifier: BSD-2-Clause
// NEON motion-compensation kernels, each equal to its plain kernel in mc.cc bit for bit:
// the separable 8-tap interpolation, the rounding of 14-bit intermediates to samples
// (single and bidirectional).
#include <arm_neon.h>

#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

inline bool identity(const int8_t* taps) { return taps[3] == 64; }

// Eight first-pass sums from the 15 samples at `src` (16 are read). The lanes wrap at 16
// bits, but the sums fit (at most 88 x 255), so they hold the plain kernel's values.
inline int16x8_t horizontal8(const uint8_t* src, const int16_t (&taps)[8]) {
  const uint8x16_t bytes = vld1q_u8(src);
  const int16x8_t low = vreinterpretq_s16_u16(vmovl_u8(vget_low_u8(bytes)));
  const int16x8_t high = vreinterpretq_s16_u16(vmovl_u8(vget_high_u8(bytes)));
  int16x8_t sum = vmulq_n_s16(low, taps[0]);
  sum = vmlaq_n_s16(sum, vextq_s16(low, high, 1), taps[1]);  // lane shifts take immediates only
  sum = vmlaq_n_s16(sum, vextq_s16(low, high, 2), taps[2]);
  sum = vmlaq_n_s16(sum, vextq_s16(low, high, 3), taps[3]);
  sum = vmlaq_n_s16(sum, vextq_s16(low, high, 4), taps[4]);
  sum = vmlaq_n_s16(sum, vextq_s16(low, high, 5), taps[5]);
  sum = vmlaq_n_s16(sum, vextq_s16(low, high, 6), taps[6]);
  return vmlaq_n_s16(sum, vextq_s16(low, high, 7), taps[7]);
}

inline void store(int16_t* out, int16x8_t value, int count) {
  if (count >= 8) {
    vst1q_s16(out, value);
  } else {
    vst1_s16(out, vget_low_s16(value));
  }
}

// First-pass rows [first_row, first_row + row_count) of the window, padded_width wide.
void first_pass(const uint8_t* window, ptrdiff_t window_stride, int first_row, int row_count, int padded_width,
                const int8_t* h_taps, int16_t* rows) {
  if (identity(h_taps)) {  // (64 t) exactly, as the plain sum gives
    for (int y = 0; y < row_count; ++y) {
      const uint8_t* src = window + (first_row + y) * window_stride + 3;
      for (int x = 0; x < padded_width; x += 8) {
        vst1q_s16(rows + y * padded_width + x, vreinterpretq_s16_u16(vshll_n_u8(vld1_u8(src + x), 6)));
      }
    }
    return;
  }
  int16_t taps[8];
  for (int i = 0; i < 8; ++i) taps[i] = h_taps[i];
  for (int y = 0; y < row_count; ++y) {
    const uint8_t* src = window + (first_row + y) * window_stride;
    for (int x = 0; x < padded_width; x += 8) vst1q_s16(rows + y * padded_width + x, horizontal8(src + x, taps));
  }
}

// The second pass in 32 bits; narrowing keeps the low 16 bits, as the plain kernel's cast.
void second_pass(const int16_t* rows, int padded_width, int width, int height, const int8_t* v_taps, int16_t* out,
                 ptrdiff_t out_stride) {
  const int16x8_t offset = vdupq_n_s16(kIntermediateOffset);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; x += 8) {
      int32x4_t low = vdupq_n_s32(0), high = vdupq_n_s32(0);
      for (int j = 0; j < 8; ++j) {
        const int16x8_t row = vld1q_s16(rows + (y + j) * padded_width + x);
        low = vmlal_n_s16(low, vget_low_s16(row), v_taps[j]);
        high = vmlal_high_n_s16(high, row, v_taps[j]);
      }
      const int16x8_t sum = vcombine_s16(vshrn_n_s32(low, 6), vshrn_n_s32(high, 6));
      store(out + y * out_stride + x, vsubq_s16(sum, offset), width - x);
    }
  }
}

void interpolate_8tap_neon(const uint8_t* window, ptrdiff_t window_stride, int width, int height,
                           const int8_t* h_taps, const int8_t* v_taps, int16_t* out, ptrdiff_t out_stride) {
  // Identity phases skip their pass, which the definition makes exact: (64 t) >> 6 = t.
  const bool vertical = !identity(v_taps);
  const int first_row = vertical ? 0 : 3, row_count = vertical ? height + 7 : height;
  const int padded_width = (width + 7) & ~7;
  alignas(16) int16_t rows[(kMaxInterpolationBlock + 7) * kMaxInterpolationBlock];
  first_pass(window, window_stride, first_row, row_count, padded_width, h_taps, rows);
  if (vertical) {
    second_pass(rows, padded_width, width, height, v_taps, out, out_stride);
    return;
  }
  const int16x8_t offset = vdupq_n_s16(kIntermediateOffset);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; x += 8) {
      store(out + y * out_stride + x, vsubq_s16(vld1q_s16(rows + y * padded_width + x), offset), width - x);
    }
  }
}

// (in + 8192 + 32) >> 6 is ((in + 32) >> 6) + 128 (8192 = 128 * 64); the rounding shift
// adds 32 without overflowing 16 bits, and the saturating narrow is the clip.
inline uint8x8_t put8(int16x8_t in) { return vqmovun_s16(vaddq_s16(vrshrq_n_s16(in, 6), vdupq_n_s16(128))); }

void put_intermediate_neon(const int16_t* in, int count, uint8_t* out) {
  int i = 0;
  for (; i + 16 <= count; i += 16)
    vst1q_u8(out + i, vcombine_u8(put8(vld1q_s16(in + i)), put8(vld1q_s16(in + i + 8))));
  if (i < count) put_intermediate_c(in + i, count - i, out + i);
}

// (a + b + 16384 + 64) >> 7 is ((((a + b) >> 1) + 32) >> 6) + 128: the bit the halving
// add drops cannot carry across a multiple of 64 after it, and neither step overflows.
inline uint8x8_t average8(int16x8_t a, int16x8_t b) {
  return vqmovun_s16(vaddq_s16(vrshrq_n_s16(vhaddq_s16(a, b), 6), vdupq_n_s16(128)));
}

void average_intermediate_neon(const int16_t* a, const int16_t* b, int count, uint8_t* out) {
  int i = 0;
  for (; i + 16 <= count; i += 16) {
    const uint8x8_t low = average8(vld1q_s16(a + i), vld1q_s16(b + i));
    vst1q_u8(out + i, vcombine_u8(low, average8(vld1q_s16(a + i + 8), vld1q_s16(b + i + 8))));
  }
  if (i < count) average_intermediate_c(a + i, b + i, count - i, out + i);
}

}  // namespace

void init_mc_neon(DspTable* table) {
  table->interpolate_8tap = interpolate_8tap_neon;
  table->put_intermediate = put_intermediate_neon;
  table->average_intermediate = average_intermediate_neon;
}

}  // namespace svc::codec::dsp
