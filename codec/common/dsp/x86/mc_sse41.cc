// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 separable 8-tap interpolation: the first pass multiplies pairs of neighbouring
// samples (gathered by pshufb) with pairs of taps (pmaddubsw, whose partial sums stay far
// below saturation for these filters: at most 88 x 255), the second pass multiplies
// pairs of first-pass rows with pairs of taps in 32 bits (pmaddwd). Identity phases skip
// their pass, which the definition makes exact: (64 t) >> 6 = t. Equal to
// interpolate_8tap_c bit for bit (tests/checkkernels).
#include <smmintrin.h>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse4.1")

namespace svc::codec::dsp {
namespace {

inline __m128i load16(const uint8_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
inline __m128i load_int16x8(const int16_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }

inline bool identity(const int8_t* taps) { return taps[3] == 64; }

// Eight first-pass sums from the 15 samples at `src` (16 are read).
inline __m128i horizontal8(const uint8_t* src, const __m128i (&pairs)[4], const __m128i (&shuffles)[4]) {
  const __m128i samples = load16(src);
  __m128i sum = _mm_maddubs_epi16(_mm_shuffle_epi8(samples, shuffles[0]), pairs[0]);
  for (int k = 1; k < 4; ++k) {
    sum = _mm_add_epi16(sum, _mm_maddubs_epi16(_mm_shuffle_epi8(samples, shuffles[k]), pairs[k]));
  }
  return sum;
}

inline void store(int16_t* out, __m128i value, int count) {
  if (count >= 8) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), value);
  } else {
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out), value);
  }
}

void interpolate_8tap_sse41(const uint8_t* window, ptrdiff_t window_stride, int width, int height,
                            const int8_t* h_taps, const int8_t* v_taps, int16_t* out, ptrdiff_t out_stride) {
  const bool vertical = !identity(v_taps);
  // First-pass rows: all height + 7 when filtering vertically, else only the block's.
  const int first_row = vertical ? 0 : 3, row_count = vertical ? height + 7 : height;
  const int padded_width = (width + 7) & ~7;
  alignas(16) int16_t rows[(kMaxInterpolationBlock + 7) * kMaxInterpolationBlock];
  if (identity(h_taps)) {
    for (int y = 0; y < row_count; ++y) {
      const uint8_t* src = window + (first_row + y) * window_stride + 3;
      for (int x = 0; x < padded_width; x += 8) {
        const __m128i samples = _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(src + x)));
        _mm_store_si128(reinterpret_cast<__m128i*>(rows + y * padded_width + x), _mm_slli_epi16(samples, 6));
      }
    }
  } else {
    __m128i pairs[4], shuffles[4];
    for (int k = 0; k < 4; ++k) {
      pairs[k] = _mm_set1_epi16(static_cast<int16_t>((h_taps[2 * k] & 0xff) | (h_taps[2 * k + 1] << 8)));
      alignas(16) int8_t order[16];
      for (int i = 0; i < 8; ++i) {
        order[2 * i] = static_cast<int8_t>(2 * k + i);
        order[2 * i + 1] = static_cast<int8_t>(2 * k + i + 1);
      }
      shuffles[k] = _mm_load_si128(reinterpret_cast<const __m128i*>(order));
    }
    for (int y = 0; y < row_count; ++y) {
      const uint8_t* src = window + (first_row + y) * window_stride;
      for (int x = 0; x < padded_width; x += 8) {
        _mm_store_si128(reinterpret_cast<__m128i*>(rows + y * padded_width + x),
                        horizontal8(src + x, pairs, shuffles));
      }
    }
  }
  const __m128i offset16 = _mm_set1_epi16(kIntermediateOffset);
  if (!vertical) {
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; x += 8) {
        store(out + y * out_stride + x, _mm_sub_epi16(load_int16x8(rows + y * padded_width + x), offset16),
              width - x);
      }
    }
    return;
  }
  __m128i pairs[4];
  for (int k = 0; k < 4; ++k) {
    pairs[k] = _mm_set1_epi32(static_cast<int32_t>((v_taps[2 * k] & 0xffff) | (v_taps[2 * k + 1] << 16)));
  }
  const __m128i offset32 = _mm_set1_epi32(kIntermediateOffset);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; x += 8) {
      __m128i low = _mm_setzero_si128(), high = _mm_setzero_si128();
      for (int k = 0; k < 4; ++k) {
        const __m128i a = load_int16x8(rows + (y + 2 * k) * padded_width + x);
        const __m128i b = load_int16x8(rows + (y + 2 * k + 1) * padded_width + x);
        low = _mm_add_epi32(low, _mm_madd_epi16(_mm_unpacklo_epi16(a, b), pairs[k]));
        high = _mm_add_epi32(high, _mm_madd_epi16(_mm_unpackhi_epi16(a, b), pairs[k]));
      }
      low = _mm_sub_epi32(_mm_srai_epi32(low, 6), offset32);
      high = _mm_sub_epi32(_mm_srai_epi32(high, 6), offset32);
      store(out + y * out_stride + x, _mm_packs_epi32(low, high), width - x);
    }
  }
}

}  // namespace

void init_mc_sse41(DspTable* table) { table->interpolate_8tap = interpolate_8tap_sse41; }

}  // namespace svc::codec::dsp

SVC_TARGET_END
