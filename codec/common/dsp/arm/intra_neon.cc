// NEON intra kernels (every block shape). Angular prediction interpolates eight samples of a row at once
// with the plain kernel's integer formula ((32 - f) a + f b + 16 is at most 8176, in
// 16-bit lanes); planar, DC and the edge preparation run the plain code. The Hadamard
// SATDs keep every value in 16 bits (residuals of at most 255 grow by 8 per 1-D pass:
// |value| <= 16320), so they equal the plain sums.
#include <arm_neon.h>

#include <cstring>

#include "codec/common/dsp/arm/transpose_neon.h"
#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

// One row of eight interpolated samples from ref[0..8].
inline uint8x8_t interpolate_row(const uint8_t* ref, int fraction) {
  const uint8x8_t a = vld1_u8(ref);
  if (fraction == 0) return a;
  const uint16x8_t sum = vmlal_u8(vmull_u8(a, vdup_n_u8(static_cast<uint8_t>(32 - fraction))), vld1_u8(ref + 1),
                                  vdup_n_u8(static_cast<uint8_t>(fraction)));
  return vrshrn_n_u16(sum, 5);  // (sum + 16) >> 5
}

// Angular prediction of an N x N block, eight samples of a row at a time (a 4x4 row
// computes eight and keeps four); horizontal modes are transposed on the way out.
template <int N>
void predict_angular(const uint8_t* edge, int mode, uint8_t* out) {
  uint8_t main[3 * N + 2 + 16];  // room for the eight-sample loads past the last sample
  std::memset(main + 3 * N + 2, 0, 16);
  const int angle = prepare_intra_angular_reference_n(edge, mode, N, main);
  const uint8_t* ref = main + N;
  uint8_t rows[N * N + 8];  // a 4x4 block's last row stores eight
  for (int y = 0; y < N; ++y) {
    const int position = (y + 1) * angle;
    for (int x = 0; x < N; x += 8)
      vst1_u8(rows + N * y + x, interpolate_row(ref + x + (position >> 5) + 1, position & 31));
  }
  if (mode >= 18) {
    std::memcpy(out, rows, N * N);
    return;
  }
  for (int y = 0; y < N; ++y) {
    for (int x = 0; x < N; ++x) out[N * x + y] = rows[N * y + x];
  }
}

template <int N>
void intra_predict_neon(const uint8_t* edge, int mode, uint8_t* out) {
  if (mode < 2) {
    if constexpr (N == 4) intra_predict_4x4_c(edge, mode, out);
    if constexpr (N == 8) intra_predict_8x8_c(edge, mode, out);
    if constexpr (N == 16) intra_predict_16x16_c(edge, mode, out);
    return;
  }
  predict_angular<N>(edge, mode, out);
  filter_intra_boundary_n(edge, mode, N, out);
}

// Rectangular blocks (16x8, 8x16, 16x4, 4x16, 8x4, 4x8): the angular modes eight samples of a row
// of the bw x bh block predicted along its columns at a time (4-wide rows keep four;
// transposed on the way out for horizontal modes); planar and DC run the plain code.
template <int W, int H>
void intra_predict_rectangular_neon(const uint8_t* edge, int mode, uint8_t* out) {
  if (mode < 2) {
    intra_predict_rectangular_c<W, H>(edge, mode, out);
    return;
  }
  uint8_t main[3 * (W + H) + 2 + 16];  // room for the eight-sample loads past the last sample
  std::memset(main + 3 * (W + H) + 2, 0, 16);
  const int angle = prepare_intra_angular_reference_rectangular(edge, mode, W, H, main);
  const uint8_t* ref = main + (W + H);
  const bool vertical = mode >= 18;
  const int bw = vertical ? W : H, bh = vertical ? H : W;
  uint8_t rows[W * H + 8];  // a 4-wide block's last row stores eight
  for (int y = 0; y < bh; ++y) {
    const int position = (y + 1) * angle;
    for (int x = 0; x < bw; x += 8)
      vst1_u8(rows + bw * y + x, interpolate_row(ref + x + (position >> 5) + 1, position & 31));
  }
  if (vertical) {
    std::memcpy(out, rows, W * H);
  } else {
    for (int y = 0; y < bh; ++y) {
      for (int x = 0; x < bw; ++x) out[W * x + y] = rows[bw * y + x];
    }
  }
  filter_intra_boundary_rectangular(edge, mode, W, H, out);
}

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

int satd_8x8_neon(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  int16x8_t v[8];
  for (int y = 0; y < 8; ++y) {
    v[y] = vreinterpretq_s16_u16(vsubl_u8(vld1_u8(source + y * source_stride), vld1_u8(prediction + 8 * y)));
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

void init_intra_neon(DspTable* table) {
  table->intra_predict_4x4 = intra_predict_neon<4>;
  table->intra_predict_8x8 = intra_predict_neon<8>;
  table->intra_predict_16x16 = intra_predict_neon<16>;
  table->intra_predict_16x8 = intra_predict_rectangular_neon<16, 8>;
  table->intra_predict_8x16 = intra_predict_rectangular_neon<8, 16>;
  table->intra_predict_16x4 = intra_predict_rectangular_neon<16, 4>;
  table->intra_predict_4x16 = intra_predict_rectangular_neon<4, 16>;
  table->intra_predict_8x4 = intra_predict_rectangular_neon<8, 4>;
  table->intra_predict_4x8 = intra_predict_rectangular_neon<4, 8>;
  table->satd_4x4 = satd_4x4_neon;
  table->satd_8x8 = satd_8x8_neon;
}

}  // namespace svc::codec::dsp
