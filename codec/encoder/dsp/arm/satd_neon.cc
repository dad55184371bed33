// SPDX-License-Identifier: BSD-2-Clause
// NEON Hadamard SATDs of the encoder's first-stage estimates (16x16: four 8x8). They keep every value
// in 16 bits (residuals of at most 255 grow by 8 per 1-D pass: |value| <= 16320), so
// they equal the plain sums.
#include <arm_neon.h>

#include <cstring>

#include "codec/common/dsp/arm/transpose_neon.h"
#include "codec/encoder/dsp/encoder_dsp_init.h"

namespace svc::codec::dsp {
namespace {

// 1-D Hadamard butterflies across N vectors (one transform per lane), in place.
template <int N, typename Vector, typename Add, typename Subtract>
void butterflies(Vector* v, Add add, Subtract subtract) {
  for (int span = 1; span < N; span *= 2) {
    for (int i = 0; i < N; i += 2 * span) {
      for (int j = i; j < i + span; ++j) {
        const Vector a = v[j], b = v[j + span];
        v[j] = add(a, b);
        v[j + span] = subtract(a, b);
      }
    }
  }
}

int satd_8x8_strided(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction,
                     ptrdiff_t prediction_stride) {
  int16x8_t v[8];
  for (int y = 0; y < 8; ++y) {
    v[y] = vreinterpretq_s16_u16(
        vsubl_u8(vld1_u8(source + y * source_stride), vld1_u8(prediction + prediction_stride * y)));
  }
  const auto add = [](int16x8_t a, int16x8_t b) { return vaddq_s16(a, b); };
  const auto subtract = [](int16x8_t a, int16x8_t b) { return vsubq_s16(a, b); };
  butterflies<8>(v, add, subtract);
  transpose_8x8(v);
  butterflies<8>(v, add, subtract);
  uint32x4_t sum = vdupq_n_u32(0);
  for (int y = 0; y < 8; ++y) sum = vpadalq_u16(sum, vreinterpretq_u16_s16(vabsq_s16(v[y])));
  return static_cast<int>(vaddvq_u32(sum));
}

int satd_8x8_neon(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  return satd_8x8_strided(source, source_stride, prediction, 8);
}

int satd_16x16_neon(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  int sum = 0;
  for (int q = 0; q < 4; ++q) {
    const int x = 8 * (q & 1), y = 8 * (q >> 1);
    sum += satd_8x8_strided(source + y * source_stride + x, source_stride, prediction + 16 * y + x, 16);
  }
  return sum;
}

int satd_4x4_neon(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  int16x4_t v[4];
  for (int y = 0; y < 4; ++y) {
    uint32_t s, p;
    std::memcpy(&s, source + y * source_stride, 4);
    std::memcpy(&p, prediction + 4 * y, 4);
    v[y] = vget_low_s16(
        vreinterpretq_s16_u16(vsubl_u8(vreinterpret_u8_u32(vdup_n_u32(s)), vreinterpret_u8_u32(vdup_n_u32(p)))));
  }
  const auto add = [](int16x4_t a, int16x4_t b) { return vadd_s16(a, b); };
  const auto subtract = [](int16x4_t a, int16x4_t b) { return vsub_s16(a, b); };
  butterflies<4>(v, add, subtract);  // down the columns
  const int16x4x2_t rows01 = vtrn_s16(v[0], v[1]), rows23 = vtrn_s16(v[2], v[3]);
  const int32x2x2_t even = vtrn_s32(vreinterpret_s32_s16(rows01.val[0]), vreinterpret_s32_s16(rows23.val[0]));
  const int32x2x2_t odd = vtrn_s32(vreinterpret_s32_s16(rows01.val[1]), vreinterpret_s32_s16(rows23.val[1]));
  int16x4_t c[4] = {vreinterpret_s16_s32(even.val[0]), vreinterpret_s16_s32(odd.val[0]),
                    vreinterpret_s16_s32(even.val[1]), vreinterpret_s16_s32(odd.val[1])};  // columns 0..3
  butterflies<4>(c, add, subtract);                                                        // along the rows
  uint32x2_t sum = vdup_n_u32(0);
  for (int x = 0; x < 4; ++x) sum = vpadal_u16(sum, vreinterpret_u16_s16(vabs_s16(c[x])));
  return static_cast<int>(vaddv_u32(sum));
}

}  // namespace

void init_satd_neon(EncoderDspTable* table) {
  table->satd_4x4 = satd_4x4_neon;
  table->satd_8x8 = satd_8x8_neon;
  table->satd_16x16 = satd_16x16_neon;
}

}  // namespace svc::codec::dsp
