// SSE4.1 deblocking kernels: the four lines of a segment side by side in 16-bit lanes
// (lanes 0..3), the decisions shared with the plain kernel (deblock_formulas.h).
#include <smmintrin.h>

#include <cstring>

#include "codec/dsp/deblock_formulas.h"
#include "codec/dsp/dsp_init.h"

#pragma GCC target("sse2,ssse3,sse4.1")

namespace svc::codec::dsp {
namespace {

// The 4 bytes at p, widened to 16-bit lanes 0..3.
inline __m128i load4(const uint8_t* p) {
  int32_t v;
  std::memcpy(&v, p, 4);
  return _mm_cvtepu8_epi16(_mm_cvtsi32_si128(v));
}

inline void store4(uint8_t* p, __m128i v) {
  const int32_t bytes = _mm_cvtsi128_si32(_mm_packus_epi16(v, v));
  std::memcpy(p, &bytes, 4);
}

// 4x4 byte transpose: groups of 4 bytes become columns.
inline __m128i transpose4x4(__m128i v) {
  return _mm_shuffle_epi8(v, _mm_setr_epi8(0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15));
}

// Samples k = -4..3 across the edge (index k + 4), each holding the four lines.
struct Columns {
  __m128i c[8];
};

Columns load_columns(const uint8_t* pixels, ptrdiff_t across, ptrdiff_t along) {
  Columns s;
  if (across == 1) {  // vertical edge: each line is 8 contiguous bytes
    __m128i lines[4];
    for (int l = 0; l < 4; ++l)
      lines[l] = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(pixels + l * along - 4));
    const __m128i l01 = _mm_unpacklo_epi8(lines[0], lines[1]), l23 = _mm_unpacklo_epi8(lines[2], lines[3]);
    const __m128i low = _mm_unpacklo_epi16(l01, l23), high = _mm_unpackhi_epi16(l01, l23);
    // Byte shifts take immediates only.
    s.c[0] = _mm_cvtepu8_epi16(low);
    s.c[1] = _mm_cvtepu8_epi16(_mm_srli_si128(low, 4));
    s.c[2] = _mm_cvtepu8_epi16(_mm_srli_si128(low, 8));
    s.c[3] = _mm_cvtepu8_epi16(_mm_srli_si128(low, 12));
    s.c[4] = _mm_cvtepu8_epi16(high);
    s.c[5] = _mm_cvtepu8_epi16(_mm_srli_si128(high, 4));
    s.c[6] = _mm_cvtepu8_epi16(_mm_srli_si128(high, 8));
    s.c[7] = _mm_cvtepu8_epi16(_mm_srli_si128(high, 12));
  } else {
    for (int k = -4; k < 4; ++k) s.c[k + 4] = load4(pixels + k * across);
  }
  return s;
}

// Writes samples k = -3..2 back (p3 and q3 never change).
void store_columns(const Columns& s, uint8_t* pixels, ptrdiff_t across, ptrdiff_t along) {
  if (across == 1) {
    const __m128i a =
        transpose4x4(_mm_packus_epi16(_mm_unpacklo_epi64(s.c[0], s.c[1]), _mm_unpacklo_epi64(s.c[2], s.c[3])));
    const __m128i b =
        transpose4x4(_mm_packus_epi16(_mm_unpacklo_epi64(s.c[4], s.c[5]), _mm_unpacklo_epi64(s.c[6], s.c[7])));
    const __m128i lines01 = _mm_unpacklo_epi32(a, b), lines23 = _mm_unpackhi_epi32(a, b);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(pixels - 4), lines01);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(pixels + along - 4), _mm_srli_si128(lines01, 8));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(pixels + 2 * along - 4), lines23);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(pixels + 3 * along - 4), _mm_srli_si128(lines23, 8));
  } else {
    for (int k = -3; k < 3; ++k) store4(pixels + k * across, s.c[k + 4]);
  }
}

inline __m128i clamp16(__m128i v, __m128i lo, __m128i hi) { return _mm_min_epi16(_mm_max_epi16(v, lo), hi); }

void strong_filter(Columns& s, int tc) {
  const __m128i p3 = s.c[0], p2 = s.c[1], p1 = s.c[2], p0 = s.c[3];
  const __m128i q0 = s.c[4], q1 = s.c[5], q2 = s.c[6], q3 = s.c[7];
  const __m128i t = _mm_set1_epi16(static_cast<int16_t>(2 * tc)), two = _mm_set1_epi16(2), four = _mm_set1_epi16(4);
  auto limit = [&](__m128i value, __m128i centre) {
    return clamp16(value, _mm_sub_epi16(centre, t), _mm_add_epi16(centre, t));
  };
  const __m128i p0q0 = _mm_add_epi16(p0, q0);
  // (p2 + 2 p1 + 2 p0 + 2 q0 + q1 + 4) >> 3 and its mirror.
  s.c[3] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_add_epi16(p2, q1), four),
                                              _mm_slli_epi16(_mm_add_epi16(p1, p0q0), 1)),
                                3),
                 p0);
  s.c[4] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_add_epi16(p1, q2), four),
                                              _mm_slli_epi16(_mm_add_epi16(q1, p0q0), 1)),
                                3),
                 q0);
  // (p2 + p1 + p0 + q0 + 2) >> 2.
  s.c[2] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(p2, p1), _mm_add_epi16(p0q0, two)), 2), p1);
  s.c[5] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(q2, q1), _mm_add_epi16(p0q0, two)), 2), q1);
  // (2 p3 + 3 p2 + p1 + p0 + q0 + 4) >> 3.
  const __m128i three_p2 = _mm_add_epi16(_mm_slli_epi16(p2, 1), p2),
                three_q2 = _mm_add_epi16(_mm_slli_epi16(q2, 1), q2);
  s.c[1] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_slli_epi16(p3, 1), three_p2),
                                              _mm_add_epi16(_mm_add_epi16(p1, p0q0), four)),
                                3),
                 p2);
  s.c[6] = limit(_mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_slli_epi16(q3, 1), three_q2),
                                              _mm_add_epi16(_mm_add_epi16(q1, p0q0), four)),
                                3),
                 q2);
}

void normal_filter(Columns& s, int tc, bool filter_p1, bool filter_q1) {
  const __m128i p2 = s.c[1], p1 = s.c[2], p0 = s.c[3], q0 = s.c[4], q1 = s.c[5], q2 = s.c[6];
  const __m128i zero = _mm_setzero_si128(), max = _mm_set1_epi16(255), one = _mm_set1_epi16(1);
  const __m128i d0 = _mm_sub_epi16(q0, p0), d1 = _mm_sub_epi16(q1, p1);
  // (9 (q0 - p0) - 3 (q1 - p1) + 8) >> 4
  const __m128i raw = _mm_srai_epi16(_mm_add_epi16(_mm_sub_epi16(_mm_add_epi16(_mm_slli_epi16(d0, 3), d0),
                                                                 _mm_add_epi16(_mm_slli_epi16(d1, 1), d1)),
                                                   _mm_set1_epi16(8)),
                                     4);
  const __m128i active = _mm_cmplt_epi16(_mm_abs_epi16(raw), _mm_set1_epi16(static_cast<int16_t>(10 * tc)));
  const __m128i tcv = _mm_set1_epi16(static_cast<int16_t>(tc));
  const __m128i delta = clamp16(raw, _mm_sub_epi16(zero, tcv), tcv);
  s.c[3] = _mm_blendv_epi8(p0, clamp16(_mm_add_epi16(p0, delta), zero, max), active);
  s.c[4] = _mm_blendv_epi8(q0, clamp16(_mm_sub_epi16(q0, delta), zero, max), active);
  const __m128i half = _mm_set1_epi16(static_cast<int16_t>(tc >> 1)), minus_half = _mm_sub_epi16(zero, half);
  if (filter_p1) {
    const __m128i mean = _mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(p2, p0), one), 1);
    const __m128i dp = clamp16(_mm_srai_epi16(_mm_add_epi16(_mm_sub_epi16(mean, p1), delta), 1), minus_half, half);
    s.c[2] = _mm_blendv_epi8(p1, clamp16(_mm_add_epi16(p1, dp), zero, max), active);
  }
  if (filter_q1) {
    const __m128i mean = _mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(q2, q0), one), 1);
    const __m128i dq = clamp16(_mm_srai_epi16(_mm_sub_epi16(_mm_sub_epi16(mean, q1), delta), 1), minus_half, half);
    s.c[5] = _mm_blendv_epi8(q1, clamp16(_mm_add_epi16(q1, dq), zero, max), active);
  }
}

void deblock_luma_sse41(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int beta, int tc) {
  const LumaDecision decision = decide_luma_segment(pixels, across, along, beta, tc);
  if (decision.filter == LumaFilter::kNone) return;
  Columns s = load_columns(pixels, across, along);
  if (decision.filter == LumaFilter::kStrong) {
    strong_filter(s, tc);
  } else {
    normal_filter(s, tc, decision.filter_p1, decision.filter_q1);
  }
  store_columns(s, pixels, across, along);
}

void deblock_chroma_sse41(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int tc) {
  __m128i p1, p0, q0, q1, columns = _mm_setzero_si128();
  if (across == 1) {  // each line is p1 p0 q0 q1: transpose the 4x4 bytes into columns
    int32_t lines[4];
    for (int l = 0; l < 4; ++l) std::memcpy(&lines[l], pixels + l * along - 2, 4);
    columns = transpose4x4(_mm_setr_epi32(lines[0], lines[1], lines[2], lines[3]));
    p1 = _mm_cvtepu8_epi16(columns);
    p0 = _mm_cvtepu8_epi16(_mm_srli_si128(columns, 4));
    q0 = _mm_cvtepu8_epi16(_mm_srli_si128(columns, 8));
    q1 = _mm_cvtepu8_epi16(_mm_srli_si128(columns, 12));
  } else {
    p1 = load4(pixels - 2 * across);
    p0 = load4(pixels - across);
    q0 = load4(pixels);
    q1 = load4(pixels + across);
  }
  const __m128i tcv = _mm_set1_epi16(static_cast<int16_t>(tc)), zero = _mm_setzero_si128();
  // ((q0 - p0) * 4 + p1 - q1 + 4) >> 3, clipped to +-tc
  const __m128i raw =
      _mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(_mm_slli_epi16(_mm_sub_epi16(q0, p0), 2), _mm_sub_epi16(p1, q1)),
                                   _mm_set1_epi16(4)),
                     3);
  const __m128i delta = clamp16(raw, _mm_sub_epi16(zero, tcv), tcv);
  const __m128i new_p0 = _mm_add_epi16(p0, delta), new_q0 = _mm_sub_epi16(q0, delta);  // packus clips to 0..255
  if (across == 1) {
    const __m128i rows =
        transpose4x4(_mm_packus_epi16(_mm_unpacklo_epi64(p1, new_p0), _mm_unpacklo_epi64(new_q0, q1)));
    int32_t lines[4];
    _mm_storeu_si128(reinterpret_cast<__m128i*>(lines), rows);
    for (int l = 0; l < 4; ++l) std::memcpy(pixels + l * along - 2, &lines[l], 4);
  } else {
    store4(pixels - across, new_p0);
    store4(pixels, new_q0);
  }
}

}  // namespace

void init_deblock_sse41(DspTable* table) {
  table->deblock_luma = deblock_luma_sse41;
  table->deblock_chroma = deblock_chroma_sse41;
}

}  // namespace svc::codec::dsp
