// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 deblocking kernels: the lines of an edge side by side in 16-bit lanes, one
// register per sample position across the edge, two segments per register (lanes 0..3
// and 4..7). Each segment's decisions are lane masks built from its lines 0 and 3, so
// the filters run without branches on both segments and blend into the samples; a
// vertical edge's eight lines are transposed into such registers and back, a horizontal
// edge's 16 samples along it fill two registers per position.
#include <smmintrin.h>

#include <algorithm>
#include <cstring>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse2,ssse3,sse4.1")

namespace svc::codec::dsp {
namespace {

// Samples k = -4..3 across the edge (index k + 4), each holding eight lines.
struct Columns {
  __m128i c[8];
};

inline __m128i clamp16(__m128i v, __m128i lo, __m128i hi) { return _mm_min_epi16(_mm_max_epi16(v, lo), hi); }
inline __m128i negate16(__m128i v) { return _mm_sub_epi16(_mm_setzero_si128(), v); }

// Each segment's line 0 (line 3) value in all four of its lanes.
inline __m128i line0_of_segments(__m128i v) {
  return _mm_shuffle_epi8(v, _mm_setr_epi8(0, 1, 0, 1, 0, 1, 0, 1, 8, 9, 8, 9, 8, 9, 8, 9));
}
inline __m128i line3_of_segments(__m128i v) {
  return _mm_shuffle_epi8(v, _mm_setr_epi8(6, 7, 6, 7, 6, 7, 6, 7, 14, 15, 14, 15, 14, 15, 14, 15));
}

// tc[0] in lanes 0..3 and tc[1] in lanes 4..7.
inline __m128i pair_tc(const uint8_t* tc) {
  return _mm_shuffle_epi8(_mm_cvtsi32_si128(tc[0] | tc[1] << 8),
                          _mm_setr_epi8(0, -1, 0, -1, 0, -1, 0, -1, 1, -1, 1, -1, 1, -1, 1, -1));
}

// --- Luma ---

// The strong filter's p2..q2 in every lane, t = 2 tc per lane.
Columns strong_filtered(const Columns& s, __m128i t) {
  const __m128i p3 = s.c[0], p2 = s.c[1], p1 = s.c[2], p0 = s.c[3];
  const __m128i q0 = s.c[4], q1 = s.c[5], q2 = s.c[6], q3 = s.c[7];
  const __m128i two = _mm_set1_epi16(2), four = _mm_set1_epi16(4);
  auto limit = [&](__m128i value, __m128i centre) {
    return clamp16(value, _mm_sub_epi16(centre, t), _mm_add_epi16(centre, t));
  };
  const __m128i p0q0 = _mm_add_epi16(p0, q0);
  Columns out = s;
  // (p2 + 2 p1 + 2 p0 + 2 q0 + q1 + 4) >> 3 and its mirror.
  out.c[3] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_add_epi16(p2, q1), four),
                                                _mm_slli_epi16(_mm_add_epi16(p1, p0q0), 1)),
                                  3),
                   p0);
  out.c[4] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_add_epi16(p1, q2), four),
                                                _mm_slli_epi16(_mm_add_epi16(q1, p0q0), 1)),
                                  3),
                   q0);
  // (p2 + p1 + p0 + q0 + 2) >> 2.
  out.c[2] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(p2, p1), _mm_add_epi16(p0q0, two)), 2), p1);
  out.c[5] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(q2, q1), _mm_add_epi16(p0q0, two)), 2), q1);
  // (2 p3 + 3 p2 + p1 + p0 + q0 + 4) >> 3.
  const __m128i three_p2 = _mm_add_epi16(_mm_slli_epi16(p2, 1), p2),
                three_q2 = _mm_add_epi16(_mm_slli_epi16(q2, 1), q2);
  out.c[1] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_slli_epi16(p3, 1), three_p2),
                                                _mm_add_epi16(_mm_add_epi16(p1, p0q0), four)),
                                  3),
                   p2);
  out.c[6] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_slli_epi16(q3, 1), three_q2),
                                                _mm_add_epi16(_mm_add_epi16(q1, p0q0), four)),
                                  3),
                   q2);
  return out;
}

// Lane masks of the per-segment decisions (docs/codec.md 5.8.1).
struct Decisions {
  __m128i strong, normal;
  __m128i p1, q1;  // the normal filter also changes p1 / q1
};

// The normal filter in the lanes of d.normal where |d| < 10 tc; sums outside 0..255
// are left for the final pack to clip.
void normal_filter(Columns& s, __m128i tc, const Decisions& d) {
  const __m128i p2 = s.c[1], p1 = s.c[2], p0 = s.c[3], q0 = s.c[4], q1 = s.c[5], q2 = s.c[6];
  const __m128i one = _mm_set1_epi16(1);
  const __m128i d0 = _mm_sub_epi16(q0, p0), d1 = _mm_sub_epi16(q1, p1);
  // (9 (q0 - p0) - 3 (q1 - p1) + 8) >> 4
  const __m128i raw = _mm_srai_epi16(_mm_add_epi16(_mm_sub_epi16(_mm_add_epi16(_mm_slli_epi16(d0, 3), d0),
                                                                 _mm_add_epi16(_mm_slli_epi16(d1, 1), d1)),
                                                   _mm_set1_epi16(8)),
                                     4);
  const __m128i ten_tc = _mm_add_epi16(_mm_slli_epi16(tc, 3), _mm_slli_epi16(tc, 1));
  const __m128i active = _mm_and_si128(d.normal, _mm_cmplt_epi16(_mm_abs_epi16(raw), ten_tc));
  const __m128i delta = clamp16(raw, negate16(tc), tc);
  s.c[3] = _mm_blendv_epi8(p0, _mm_add_epi16(p0, delta), active);
  s.c[4] = _mm_blendv_epi8(q0, _mm_sub_epi16(q0, delta), active);
  const __m128i half = _mm_srai_epi16(tc, 1), minus_half = negate16(half);
  const __m128i p_mean = _mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(p2, p0), one), 1);
  const __m128i dp = clamp16(_mm_srai_epi16(_mm_add_epi16(_mm_sub_epi16(p_mean, p1), delta), 1), minus_half, half);
  s.c[2] = _mm_blendv_epi8(p1, _mm_add_epi16(p1, dp), _mm_and_si128(active, d.p1));
  const __m128i q_mean = _mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(q2, q0), one), 1);
  const __m128i dq = clamp16(_mm_srai_epi16(_mm_sub_epi16(_mm_sub_epi16(q_mean, q1), delta), 1), minus_half, half);
  s.c[5] = _mm_blendv_epi8(q1, _mm_add_epi16(q1, dq), _mm_and_si128(active, d.q1));
}

// Whether each line is flat and even enough for the strong filter (docs/codec.md 5.8.1).
__m128i strong_lines(const Columns& s, __m128i dpq, __m128i tc, int beta) {
  const __m128i p3 = s.c[0], p0 = s.c[3], q0 = s.c[4], q3 = s.c[7];
  const __m128i flat = _mm_cmplt_epi16(_mm_slli_epi16(dpq, 1), _mm_set1_epi16(static_cast<int16_t>(beta >> 2)));
  const __m128i ends = _mm_add_epi16(_mm_abs_epi16(_mm_sub_epi16(p3, p0)), _mm_abs_epi16(_mm_sub_epi16(q0, q3)));
  const __m128i even = _mm_cmplt_epi16(ends, _mm_set1_epi16(static_cast<int16_t>(beta >> 3)));
  const __m128i step_limit =
      _mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_slli_epi16(tc, 2), tc), _mm_set1_epi16(1)), 1);
  const __m128i small_step = _mm_cmplt_epi16(_mm_abs_epi16(_mm_sub_epi16(p0, q0)), step_limit);
  return _mm_and_si128(_mm_and_si128(flat, even), small_step);
}

// Filters the segments in lanes 0..3 and 4..7 of `s` with tc per lane (0: left alone);
// false, with `s` untouched, when neither segment is filtered.
bool filter_segment_pair(Columns& s, __m128i tc, int beta) {
  const __m128i p2 = s.c[1], p1 = s.c[2], p0 = s.c[3], q0 = s.c[4], q1 = s.c[5], q2 = s.c[6];
  // Second differences on each side: how textured the edge's surroundings are.
  const __m128i dp = _mm_abs_epi16(_mm_sub_epi16(_mm_add_epi16(p2, p0), _mm_slli_epi16(p1, 1)));
  const __m128i dq = _mm_abs_epi16(_mm_sub_epi16(_mm_add_epi16(q2, q0), _mm_slli_epi16(q1, 1)));
  const __m128i dp_03 = _mm_add_epi16(line0_of_segments(dp), line3_of_segments(dp));
  const __m128i dq_03 = _mm_add_epi16(line0_of_segments(dq), line3_of_segments(dq));
  const __m128i smooth = _mm_cmplt_epi16(_mm_add_epi16(dp_03, dq_03), _mm_set1_epi16(static_cast<int16_t>(beta)));
  const __m128i on = _mm_andnot_si128(_mm_cmpeq_epi16(tc, _mm_setzero_si128()), smooth);
  if (_mm_testz_si128(on, on)) return false;  // common on textured content: skip the filters
  const __m128i strong_line = strong_lines(s, _mm_add_epi16(dp, dq), tc, beta);
  Decisions d;
  d.strong = _mm_and_si128(on, _mm_and_si128(line0_of_segments(strong_line), line3_of_segments(strong_line)));
  d.normal = _mm_andnot_si128(d.strong, on);
  const __m128i side_threshold = _mm_set1_epi16(static_cast<int16_t>((beta + (beta >> 1)) >> 3));
  d.p1 = _mm_cmplt_epi16(dp_03, side_threshold);
  d.q1 = _mm_cmplt_epi16(dq_03, side_threshold);
  const Columns strong = strong_filtered(s, _mm_add_epi16(tc, tc));
  normal_filter(s, tc, d);
  for (int k = 1; k < 7; ++k) s.c[k] = _mm_blendv_epi8(s.c[k], strong.c[k], d.strong);
  return true;
}

// 8x8 byte transpose of registers holding two 8-byte rows each ([row 0 | row 1], ...)
// into [column 0 | column 1], ...; its own inverse.
void transpose8x8(__m128i v[4]) {
  const __m128i t0 = _mm_unpacklo_epi8(v[0], v[1]), t1 = _mm_unpackhi_epi8(v[0], v[1]);
  const __m128i t2 = _mm_unpacklo_epi8(v[2], v[3]), t3 = _mm_unpackhi_epi8(v[2], v[3]);
  const __m128i u0 = _mm_unpacklo_epi8(t0, t1), u1 = _mm_unpackhi_epi8(t0, t1);
  const __m128i u2 = _mm_unpacklo_epi8(t2, t3), u3 = _mm_unpackhi_epi8(t2, t3);
  v[0] = _mm_unpacklo_epi32(u0, u2);
  v[1] = _mm_unpackhi_epi32(u0, u2);
  v[2] = _mm_unpacklo_epi32(u1, u3);
  v[3] = _mm_unpackhi_epi32(u1, u3);
}

inline __m128i load_two_rows(const uint8_t* first, const uint8_t* second) {
  const __m128i low = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(first));
  return _mm_castpd_si128(_mm_loadh_pd(_mm_castsi128_pd(low), reinterpret_cast<const double*>(second)));
}

inline void store_two_rows(uint8_t* first, uint8_t* second, __m128i v) {
  _mm_storel_epi64(reinterpret_cast<__m128i*>(first), v);
  _mm_storeh_pd(reinterpret_cast<double*>(second), _mm_castsi128_pd(v));
}

// Two segments of a vertical edge: eight lines of p3..q3, transposed.
void filter_vertical_pair(uint8_t* pixels, ptrdiff_t along, int beta, const uint8_t* tc) {
  uint8_t* line = pixels - 4;
  __m128i v[4];
  for (int i = 0; i < 4; ++i) v[i] = load_two_rows(line + 2 * i * along, line + (2 * i + 1) * along);
  transpose8x8(v);
  Columns s;
  for (int i = 0; i < 4; ++i) {
    s.c[2 * i] = _mm_cvtepu8_epi16(v[i]);
    s.c[2 * i + 1] = _mm_unpackhi_epi8(v[i], _mm_setzero_si128());
  }
  if (!filter_segment_pair(s, pair_tc(tc), beta)) return;
  for (int i = 0; i < 4; ++i) v[i] = _mm_packus_epi16(s.c[2 * i], s.c[2 * i + 1]);
  transpose8x8(v);
  for (int i = 0; i < 4; ++i) store_two_rows(line + 2 * i * along, line + (2 * i + 1) * along, v[i]);
}

// Four segments of a horizontal edge: 16 contiguous samples at each position across it.
void filter_horizontal_quad(uint8_t* pixels, ptrdiff_t across, int beta, const uint8_t* tc) {
  Columns low, high;
  for (int k = -4; k < 4; ++k) {
    const __m128i row = _mm_loadu_si128(reinterpret_cast<const __m128i*>(pixels + k * across));
    low.c[k + 4] = _mm_cvtepu8_epi16(row);
    high.c[k + 4] = _mm_unpackhi_epi8(row, _mm_setzero_si128());
  }
  const bool low_filtered = filter_segment_pair(low, pair_tc(tc), beta);
  const bool high_filtered = filter_segment_pair(high, pair_tc(tc + 2), beta);
  if (!low_filtered && !high_filtered) return;
  for (int k = -3; k < 3; ++k) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(pixels + k * across),
                     _mm_packus_epi16(low.c[k + 4], high.c[k + 4]));
  }
}

// One or two segments of a horizontal edge (`count`), after its groups of four.
void filter_horizontal_rest(uint8_t* pixels, ptrdiff_t across, int count, int beta, const uint8_t* tc) {
  auto load = [&](const uint8_t* p) {
    if (count == 2) return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p));
    int32_t bytes;
    std::memcpy(&bytes, p, 4);
    return _mm_cvtsi32_si128(bytes);
  };
  Columns s;
  for (int k = -4; k < 4; ++k) s.c[k + 4] = _mm_cvtepu8_epi16(load(pixels + k * across));
  const uint8_t pair[2] = {tc[0], count == 2 ? tc[1] : uint8_t{0}};
  if (!filter_segment_pair(s, pair_tc(pair), beta)) return;
  for (int k = -3; k < 3; ++k) {
    const __m128i bytes = _mm_packus_epi16(s.c[k + 4], s.c[k + 4]);
    uint8_t* row = pixels + k * across;
    if (count == 2) {
      _mm_storel_epi64(reinterpret_cast<__m128i*>(row), bytes);
    } else {
      const int32_t word = _mm_cvtsi128_si32(bytes);
      std::memcpy(row, &word, 4);
    }
  }
}

// The last segment of a vertical edge with an odd number: four lines, lanes 4..7 idle.
void filter_vertical_single(uint8_t* pixels, ptrdiff_t along, int beta, uint8_t tc) {
  uint8_t* line = pixels - 4;
  __m128i v[4];
  for (int i = 0; i < 2; ++i) v[i] = load_two_rows(line + 2 * i * along, line + (2 * i + 1) * along);
  v[2] = v[3] = _mm_setzero_si128();
  transpose8x8(v);
  Columns s;
  for (int i = 0; i < 4; ++i) {
    s.c[2 * i] = _mm_cvtepu8_epi16(v[i]);
    s.c[2 * i + 1] = _mm_unpackhi_epi8(v[i], _mm_setzero_si128());
  }
  const uint8_t pair[2] = {tc, 0};
  if (!filter_segment_pair(s, pair_tc(pair), beta)) return;
  for (int i = 0; i < 4; ++i) v[i] = _mm_packus_epi16(s.c[2 * i], s.c[2 * i + 1]);
  transpose8x8(v);
  for (int i = 0; i < 2; ++i) store_two_rows(line + 2 * i * along, line + (2 * i + 1) * along, v[i]);
}

void deblock_luma_sse41(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int segments, int beta,
                        const uint8_t* tc) {
  int s = 0;
  if (across == 1) {
    for (; s + 2 <= segments; s += 2) {
      if ((tc[s] | tc[s + 1]) != 0) filter_vertical_pair(pixels + 4 * s * along, along, beta, tc + s);
    }
    if (s < segments && tc[s] != 0) filter_vertical_single(pixels + 4 * s * along, along, beta, tc[s]);
    return;
  }
  for (; s + 4 <= segments; s += 4) {
    if ((tc[s] | tc[s + 1] | tc[s + 2] | tc[s + 3]) != 0)
      filter_horizontal_quad(pixels + 4 * s, across, beta, tc + s);
  }
  for (; s < segments; s += 2) {
    const int count = std::min(segments - s, 2);
    if ((tc[s] | tc[s + count - 1]) != 0) filter_horizontal_rest(pixels + 4 * s, across, count, beta, tc + s);
  }
}

// --- Chroma ---

// p0 and q0 filtered with tc per lane (0: unchanged); the pack clips them to 0..255.
inline void chroma_filter(__m128i p1, __m128i& p0, __m128i& q0, __m128i q1, __m128i tc) {
  // ((q0 - p0) * 4 + p1 - q1 + 4) >> 3, clipped to +-tc
  const __m128i raw =
      _mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_slli_epi16(_mm_sub_epi16(q0, p0), 2), _mm_sub_epi16(p1, q1)),
                                   _mm_set1_epi16(4)),
                     3);
  const __m128i delta = clamp16(raw, negate16(tc), tc);
  p0 = _mm_add_epi16(p0, delta);
  q0 = _mm_sub_epi16(q0, delta);
}

// 4x4 byte transpose: groups of 4 bytes become columns.
inline __m128i transpose4x4(__m128i v) {
  return _mm_shuffle_epi8(v, _mm_setr_epi8(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15));
}

// Two segments of a vertical chroma edge: eight lines p1 p0 q0 q1, each 4 bytes.
void chroma_vertical_pair(uint8_t* pixels, ptrdiff_t along, const uint8_t* tc) {
  int32_t lines[8];
  for (int l = 0; l < 8; ++l) std::memcpy(&lines[l], pixels + l * along - 2, 4);
  // [p1 | p0 | q0 | q1] of lines 0..3 and of lines 4..7, then p1, p0 (q0, q1) of all eight.
  const __m128i top = transpose4x4(_mm_loadu_si128(reinterpret_cast<const __m128i*>(lines)));
  const __m128i bottom = transpose4x4(_mm_loadu_si128(reinterpret_cast<const __m128i*>(lines + 4)));
  const __m128i p = _mm_unpacklo_epi32(top, bottom), q = _mm_unpackhi_epi32(top, bottom);
  const __m128i zero = _mm_setzero_si128();
  const __m128i p1 = _mm_cvtepu8_epi16(p), q1 = _mm_unpackhi_epi8(q, zero);
  __m128i p0 = _mm_unpackhi_epi8(p, zero), q0 = _mm_cvtepu8_epi16(q);
  chroma_filter(p1, p0, q0, q1, pair_tc(tc));
  // Back to [p1 | p0 | q0 | q1] per four lines: dwords 0, 2 of each half, then 1, 3.
  const __m128i new_p = _mm_shuffle_epi32(_mm_packus_epi16(p1, p0), 0xD8);
  const __m128i new_q = _mm_shuffle_epi32(_mm_packus_epi16(q0, q1), 0xD8);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(lines), transpose4x4(_mm_unpacklo_epi64(new_p, new_q)));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(lines + 4), transpose4x4(_mm_unpackhi_epi64(new_p, new_q)));
  for (int l = 0; l < 8; ++l) std::memcpy(pixels + l * along - 2, &lines[l], 4);
}

// Four segments of a horizontal chroma edge: 16 samples along it.
void chroma_horizontal_quad(uint8_t* pixels, ptrdiff_t across, const uint8_t* tc) {
  __m128i low[4], high[4];
  for (int k = -2; k < 2; ++k) {
    const __m128i row = _mm_loadu_si128(reinterpret_cast<const __m128i*>(pixels + k * across));
    low[k + 2] = _mm_cvtepu8_epi16(row);
    high[k + 2] = _mm_unpackhi_epi8(row, _mm_setzero_si128());
  }
  chroma_filter(low[0], low[1], low[2], low[3], pair_tc(tc));
  chroma_filter(high[0], high[1], high[2], high[3], pair_tc(tc + 2));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(pixels - across), _mm_packus_epi16(low[1], high[1]));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(pixels), _mm_packus_epi16(low[2], high[2]));
}

// One segment of either edge: four lines.
void chroma_single(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int tc) {
  __m128i rows[4];  // p1, p0, q0, q1 in lanes 0..3
  int32_t words[4];
  for (int i = 0; i < 4; ++i)
    std::memcpy(&words[i], across == 1 ? pixels + i * along - 2 : pixels + (i - 2) * across, 4);
  __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(words));
  if (across == 1) bytes = transpose4x4(bytes);  // each line is p1 p0 q0 q1
  rows[0] = _mm_cvtepu8_epi16(bytes);
  rows[1] = _mm_cvtepu8_epi16(_mm_srli_si128(bytes, 4));
  rows[2] = _mm_cvtepu8_epi16(_mm_srli_si128(bytes, 8));
  rows[3] = _mm_cvtepu8_epi16(_mm_srli_si128(bytes, 12));
  chroma_filter(rows[0], rows[1], rows[2], rows[3], _mm_set1_epi16(static_cast<int16_t>(tc)));
  bytes = _mm_packus_epi16(_mm_unpacklo_epi64(rows[0], rows[1]), _mm_unpacklo_epi64(rows[2], rows[3]));
  if (across == 1) bytes = transpose4x4(bytes);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(words), bytes);
  for (int i = 0; i < 4; ++i)
    std::memcpy(across == 1 ? pixels + i * along - 2 : pixels + (i - 2) * across, &words[i], 4);
}

void deblock_chroma_sse41(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int segments, const uint8_t* tc) {
  int s = 0;
  if (across == 1) {
    for (; s + 2 <= segments; s += 2) {
      if ((tc[s] | tc[s + 1]) != 0) chroma_vertical_pair(pixels + 4 * s * along, along, tc + s);
    }
  } else {
    for (; s + 4 <= segments; s += 4) {
      if ((tc[s] | tc[s + 1] | tc[s + 2] | tc[s + 3]) != 0) chroma_horizontal_quad(pixels + 4 * s, across, tc + s);
    }
  }
  for (; s < segments; ++s) {
    if (tc[s] != 0) chroma_single(pixels + 4 * s * along, across, along, tc[s]);
  }
}

}  // namespace

void init_deblock_sse41(DspTable* table) {
  table->deblock_luma = deblock_luma_sse41;
  table->deblock_chroma = deblock_chroma_sse41;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
