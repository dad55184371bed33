// SPDX-License-Identifier: BSD-2-Clause
// NEON intra kernels (every block shape). Angular prediction interpolates eight samples of a row at once
// with the plain kernel's integer formula ((32 - f) a + f b + 16 is at most 8176, in
// 16-bit lanes); planar, DC and the edge preparation run the plain code.
#include <arm_neon.h>

#include <cstring>

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
  const int angle = prepare_intra_angular_reference(edge, mode, transform_size_of(N, N), main);
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
  filter_intra_boundary(edge, mode, transform_size_of(N, N), out);
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
  const int angle = prepare_intra_angular_reference(edge, mode, transform_size_of(W, H), main);
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
  filter_intra_boundary(edge, mode, transform_size_of(W, H), out);
}

}  // namespace

void init_intra_neon(DspTable* table) {
  table->intra_predict[size_index(TransformSize::k4x4)] = intra_predict_neon<4>;
  table->intra_predict[size_index(TransformSize::k8x8)] = intra_predict_neon<8>;
  table->intra_predict[size_index(TransformSize::k16x16)] = intra_predict_neon<16>;
  table->intra_predict[size_index(TransformSize::k16x8)] = intra_predict_rectangular_neon<16, 8>;
  table->intra_predict[size_index(TransformSize::k8x16)] = intra_predict_rectangular_neon<8, 16>;
  table->intra_predict[size_index(TransformSize::k16x4)] = intra_predict_rectangular_neon<16, 4>;
  table->intra_predict[size_index(TransformSize::k4x16)] = intra_predict_rectangular_neon<4, 16>;
  table->intra_predict[size_index(TransformSize::k8x4)] = intra_predict_rectangular_neon<8, 4>;
  table->intra_predict[size_index(TransformSize::k4x8)] = intra_predict_rectangular_neon<4, 8>;
}

}  // namespace svc::codec::dsp
