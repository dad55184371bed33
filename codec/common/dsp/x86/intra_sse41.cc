// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 intra kernels (every block shape). Angular prediction interpolates a whole row
// at once with the plain kernel's integer formula and planar a row of eight samples at
// once; DC and the edge preparation run the plain code.
#include <smmintrin.h>

#include <bit>
#include <cstring>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse4.1")

#include "codec/common/dsp/x86/transpose_sse2.h"

namespace svc::codec::dsp {
namespace {

// One row of eight interpolated samples ((32 - f) a + f b + 16) >> 5 from ref[0..8].
__m128i interpolate_row(const uint8_t* ref, int fraction) {
  const __m128i a = _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(ref)));
  if (fraction == 0) return a;
  const __m128i b = _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(ref + 1)));
  const __m128i sum = _mm_add_epi16(_mm_mullo_epi16(a, _mm_set1_epi16(static_cast<int16_t>(32 - fraction))),
                                    _mm_mullo_epi16(b, _mm_set1_epi16(static_cast<int16_t>(fraction))));
  return _mm_srli_epi16(_mm_add_epi16(sum, _mm_set1_epi16(16)), 5);
}

// Planar prediction from the smoothed edge, eight samples of a row per register (a 4x4
// row computes eight and keeps four): row y is the row-0 sum plus y (below_left -
// above[x]) plus (N - 1 - x) left[y], all exact in 16 bits (at most 62 * 255 + 16).
template <int N>
void predict_planar(const uint8_t* edge, uint8_t* out) {
  constexpr int kCorner = 2 * N, kShift = N == 4 ? 3 : N == 8 ? 4 : 5;
  uint8_t smoothed[4 * N + 1 + 8];  // room for the eight-sample load of a 4x4 block's above row
  smooth_intra_edge(edge, transform_size_of(N, N), smoothed);
  std::memset(smoothed + 4 * N + 1, 0, 8);
  const uint8_t* above = smoothed + kCorner + 1;
  const __m128i above_right = _mm_set1_epi16(above[N]), below_left = _mm_set1_epi16(smoothed[kCorner - 1 - N]);
  const __m128i lane = _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7);
  for (int x = 0; x < N; x += 8) {
    const __m128i position = _mm_add_epi16(lane, _mm_set1_epi16(static_cast<int16_t>(x)));
    const __m128i right_weight = _mm_add_epi16(position, _mm_set1_epi16(1));
    const __m128i left_weight = _mm_sub_epi16(_mm_set1_epi16(N - 1), position);
    const __m128i top = _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(above + x)));
    __m128i sum =
        _mm_add_epi16(_mm_mullo_epi16(right_weight, above_right), _mm_mullo_epi16(top, _mm_set1_epi16(N - 1)));
    sum = _mm_add_epi16(sum, _mm_add_epi16(below_left, _mm_set1_epi16(N)));
    const __m128i step = _mm_sub_epi16(below_left, top);
    for (int y = 0; y < N; ++y) {
      const __m128i left = _mm_set1_epi16(smoothed[kCorner - 1 - y]);
      const __m128i row = _mm_srli_epi16(_mm_add_epi16(sum, _mm_mullo_epi16(left_weight, left)), kShift);
      uint8_t packed[16];
      _mm_storeu_si128(reinterpret_cast<__m128i*>(packed), _mm_packus_epi16(row, row));
      std::memcpy(out + N * y + x, packed, N < 8 ? N : 8);
      sum = _mm_add_epi16(sum, step);
    }
  }
}

void intra_predict_8x8_sse41(const uint8_t* edge, int mode, uint8_t* out) {
  if (mode == 0) {
    predict_planar<8>(edge, out);
    return;
  }
  if (mode == 1) {
    intra_predict_8x8_c(edge, mode, out);
    return;
  }
  IntraAngularReference reference;
  prepare_intra_angular_reference(edge, mode, &reference);
  const uint8_t* ref = reference.main + kIntraAngularReferenceOffset;
  __m128i rows[8];
  for (int y = 0; y < 8; ++y) {
    const int position = (y + 1) * reference.angle;
    rows[y] = interpolate_row(ref + (position >> 5) + 1, position & 31);
  }
  if (mode < 18) transpose_8x8_epi16(rows);
  for (int y = 0; y < 8; y += 2) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 8 * y), _mm_packus_epi16(rows[y], rows[y + 1]));
  }
  filter_intra_boundary(edge, mode, TransformSize::k8x8, out);
}

// Angular prediction of a 16x16 block, eight samples of a row at a time; horizontal
// modes are transposed on the way out.
template <int N>
void predict_angular(const uint8_t* edge, int mode, uint8_t* out) {
  uint8_t main[3 * N + 2 + 16];  // room for the eight-sample loads past the last sample
  std::memset(main + 3 * N + 2, 0, 16);
  const int angle = prepare_intra_angular_reference(edge, mode, transform_size_of(N, N), main);
  const uint8_t* ref = main + N;
  alignas(16) uint8_t rows[N * N + 16];
  for (int y = 0; y < N; ++y) {
    const int position = (y + 1) * angle;
    for (int x = 0; x < N; x += 8) {
      const __m128i row = interpolate_row(ref + x + (position >> 5) + 1, position & 31);
      uint8_t packed[16];
      _mm_storeu_si128(reinterpret_cast<__m128i*>(packed), _mm_packus_epi16(row, row));
      std::memcpy(rows + N * y + x, packed, N < 8 ? N : 8);
    }
  }
  if (mode >= 18) {
    std::memcpy(out, rows, N * N);
  } else {
    for (int y = 0; y < N; ++y) {
      for (int x = 0; x < N; ++x) out[N * x + y] = rows[N * y + x];
    }
  }
  filter_intra_boundary(edge, mode, transform_size_of(N, N), out);
}

// A 4x4 block's angular rows, eight samples computed to keep four, measured slower than
// the plain loop (svc-checkkernels --bench): only planar has a variant.
void intra_predict_4x4_sse41(const uint8_t* edge, int mode, uint8_t* out) {
  if (mode == 0) {
    predict_planar<4>(edge, out);
    return;
  }
  intra_predict_4x4_c(edge, mode, out);
}

void intra_predict_16x16_sse41(const uint8_t* edge, int mode, uint8_t* out) {
  if (mode == 0) {
    predict_planar<16>(edge, out);
    return;
  }
  if (mode == 1) {
    intra_predict_16x16_c(edge, mode, out);
    return;
  }
  predict_angular<16>(edge, mode, out);
}

// Stores the first `count` (at most 8) samples of a row of 16-bit lanes.
inline void store_row(__m128i row, int count, uint8_t* out) {
  if (count == 8) {
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out), _mm_packus_epi16(row, row));
    return;
  }
  uint8_t packed[16];
  _mm_storeu_si128(reinterpret_cast<__m128i*>(packed), _mm_packus_epi16(row, row));
  std::memcpy(out, packed, static_cast<size_t>(count));
}

// Rectangular blocks (16x8, 8x16, 16x4, 4x16). Planar: a row of eight samples per
// register (a 4-wide block computes eight and keeps four), the vertical term
// ((H - 1 - y) above[x] + (y + 1) left[H]) stepped by (left[H] - above[x]) per row and
// the horizontal one ((W - 1 - x) left[y] + (x + 1) above[W]) formed per row, each shifted
// up by the other side's log2; the sum is at most 2 * 16 * 255 * 8 + 128 = 65408, exact
// in unsigned 16-bit lanes (modular steps, logical shift).
template <int W, int H>
void predict_rectangular_planar(const uint8_t* edge, uint8_t* out) {
  constexpr int kCorner = W + H, kLogW = std::bit_width(unsigned{W}) - 1, kLogH = std::bit_width(unsigned{H}) - 1;
  uint8_t smoothed[2 * (W + H) + 1 + 8];  // room for the eight-sample load of a 4-wide above row
  smooth_intra_edge(edge, transform_size_of(W, H), smoothed);
  const uint8_t* above = smoothed + kCorner + 1;
  const __m128i below_left = _mm_set1_epi16(smoothed[kCorner - 1 - H]), above_right = _mm_set1_epi16(above[W]);
  const __m128i lane = _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7);
  for (int x = 0; x < W; x += 8) {
    const __m128i position = _mm_add_epi16(lane, _mm_set1_epi16(static_cast<int16_t>(x)));
    const __m128i left_weight = _mm_sub_epi16(_mm_set1_epi16(W - 1), position);
    const __m128i right_term = _mm_mullo_epi16(_mm_add_epi16(position, _mm_set1_epi16(1)), above_right);
    const __m128i top = _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(above + x)));
    __m128i vertical = _mm_add_epi16(_mm_mullo_epi16(top, _mm_set1_epi16(H - 1)), below_left);
    const __m128i step = _mm_sub_epi16(below_left, top);
    for (int y = 0; y < H; ++y) {
      const __m128i left = _mm_set1_epi16(smoothed[kCorner - 1 - y]);
      const __m128i horizontal = _mm_add_epi16(_mm_mullo_epi16(left_weight, left), right_term);
      __m128i sum = _mm_add_epi16(_mm_slli_epi16(vertical, kLogW), _mm_slli_epi16(horizontal, kLogH));
      sum = _mm_srli_epi16(_mm_add_epi16(sum, _mm_set1_epi16(W * H)), kLogW + kLogH + 1);
      store_row(sum, W < 8 ? W : 8, out + W * y + x);
      vertical = _mm_add_epi16(vertical, step);
    }
  }
}

// Angular: eight samples of a row of the bw x bh block predicted along its columns at a
// time (4-wide rows keep four); horizontal modes transpose it on the way out in 8x8
// tiles of 16-bit samples. DC runs the plain code.
template <int W, int H>
void intra_predict_rectangular_sse41(const uint8_t* edge, int mode, uint8_t* out) {
  if (mode == 0) return predict_rectangular_planar<W, H>(edge, out);
  if (mode == 1) {
    intra_predict_rectangular_c<W, H>(edge, mode, out);
    return;
  }
  uint8_t main[3 * (W + H) + 2 + 16];  // room for the eight-sample loads past the last sample
  std::memset(main + 3 * (W + H) + 2, 0, 16);
  const int angle = prepare_intra_angular_reference(edge, mode, transform_size_of(W, H), main);
  const uint8_t* ref = main + (W + H);
  const bool vertical = mode >= 18;
  const int bw = vertical ? W : H, bh = vertical ? H : W;
  __m128i rows[16][2];  // [y][x / 8] of the bw x bh block
  for (int y = 0; y < bh; ++y) {
    const int position = (y + 1) * angle;
    for (int x = 0; x < bw; x += 8) rows[y][x / 8] = interpolate_row(ref + x + (position >> 5) + 1, position & 31);
  }
  if (vertical) {
    for (int y = 0; y < H; ++y) {
      for (int x = 0; x < W; x += 8) store_row(rows[y][x / 8], W < 8 ? W : 8, out + W * y + x);
    }
  } else {
    for (int ty = 0; ty < bh; ty += 8) {
      for (int tx = 0; tx < bw; tx += 8) {
        __m128i tile[8];
        for (int i = 0; i < 8; ++i) tile[i] = rows[ty + i < bh ? ty + i : 0][tx / 8];
        transpose_8x8_epi16(tile);  // tile[i]: column tx + i, rows ty..ty + 7: output row tx + i
        for (int i = 0; i < 8 && tx + i < bw; ++i) store_row(tile[i], bh < 8 ? bh : 8, out + W * (tx + i) + ty);
      }
    }
  }
  filter_intra_boundary(edge, mode, transform_size_of(W, H), out);
}

}  // namespace

void init_intra_sse41(DspTable* table) {
  table->intra_predict[size_index(TransformSize::k16x8)] = intra_predict_rectangular_sse41<16, 8>;
  table->intra_predict[size_index(TransformSize::k8x16)] = intra_predict_rectangular_sse41<8, 16>;
  table->intra_predict[size_index(TransformSize::k16x4)] = intra_predict_rectangular_sse41<16, 4>;
  table->intra_predict[size_index(TransformSize::k4x16)] = intra_predict_rectangular_sse41<4, 16>;
  table->intra_predict[size_index(TransformSize::k8x4)] = intra_predict_rectangular_sse41<8, 4>;
  table->intra_predict[size_index(TransformSize::k4x8)] = intra_predict_rectangular_sse41<4, 8>;
  table->intra_predict[size_index(TransformSize::k4x4)] = intra_predict_4x4_sse41;
  table->intra_predict[size_index(TransformSize::k8x8)] = intra_predict_8x8_sse41;
  table->intra_predict[size_index(TransformSize::k16x16)] = intra_predict_16x16_sse41;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
