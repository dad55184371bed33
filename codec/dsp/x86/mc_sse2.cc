// SSE2 motion-compensation kernels: pavgb is exactly (a + b + 1) >> 1 and psadbw a
// 16-sample SAD, so each matches the plain kernel in mc.cc bit for bit.
#include <emmintrin.h>

#include "codec/dsp/dsp_init.h"

#pragma GCC target("sse2")

namespace svc::codec::dsp {
namespace {

inline __m128i load8(const uint8_t* p) { return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)); }
inline __m128i load16(const uint8_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }

// (a + b + c + d + 2) >> 2 per byte, exactly: the mean of the two pair means, less the
// one that rounding twice adds (when a pair's sum and the means' sum are both odd).
inline __m128i average4_epu8(__m128i a, __m128i b, __m128i c, __m128i d) {
  const __m128i ab = _mm_avg_epu8(a, b), cd = _mm_avg_epu8(c, d);
  const __m128i odd = _mm_or_si128(_mm_xor_si128(a, b), _mm_xor_si128(c, d));
  const __m128i excess = _mm_and_si128(_mm_and_si128(odd, _mm_xor_si128(ab, cd)), _mm_set1_epi8(1));
  return _mm_sub_epi8(_mm_avg_epu8(ab, cd), excess);
}

// One row of half-pel interpolation from `load` (8 or 16 samples).
template <typename Load>
inline __m128i half_pel_row(Load load, const uint8_t* row, ptrdiff_t stride, int fx, int fy) {
  if (fy == 0) return fx == 0 ? load(row) : _mm_avg_epu8(load(row), load(row + 1));
  const uint8_t* below = row + stride;
  if (fx == 0) return _mm_avg_epu8(load(row), load(below));
  return average4_epu8(load(row), load(row + 1), load(below), load(below + 1));
}

// Macroblock luma (16) and chroma (8) widths; other sizes take the plain kernel.
void put_half_pel_sse2(const uint8_t* window, ptrdiff_t window_stride, int width, int height, int fx, int fy,
                       uint8_t* out, ptrdiff_t out_stride) {
  if (width == 16) {
    for (int y = 0; y < height; ++y) {
      const __m128i value = half_pel_row(load16, window + y * window_stride, window_stride, fx, fy);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + y * out_stride), value);
    }
  } else if (width == 8) {
    for (int y = 0; y < height; ++y) {
      const __m128i value = half_pel_row(load8, window + y * window_stride, window_stride, fx, fy);
      _mm_storel_epi64(reinterpret_cast<__m128i*>(out + y * out_stride), value);
    }
  } else {
    put_half_pel_c(window, window_stride, width, height, fx, fy, out, out_stride);
  }
}

void average_sse2(const uint8_t* a, const uint8_t* b, int count, uint8_t* out) {
  int i = 0;
  for (; i + 16 <= count; i += 16) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), _mm_avg_epu8(load16(a + i), load16(b + i)));
  }
  for (; i < count; ++i) out[i] = static_cast<uint8_t>((a[i] + b[i] + 1) >> 1);
}

inline int horizontal_sum(__m128i sad) {
  return _mm_cvtsi128_si32(sad) + _mm_cvtsi128_si32(_mm_srli_si128(sad, 8));
}

int sad_16x16_sse2(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  __m128i sum = _mm_setzero_si128();
  for (int y = 0; y < 16; ++y) {
    sum = _mm_add_epi64(sum, _mm_sad_epu8(load16(source + y * source_stride), load16(prediction + 16 * y)));
  }
  return horizontal_sum(sum);
}

int sad_half_pel_16x16_sse2(const uint8_t* reference, ptrdiff_t reference_stride, int fx, int fy,
                            const uint8_t* source, ptrdiff_t source_stride, int limit) {
  int sum = 0;
  for (int y = 0; y < 16; ++y) {
    const __m128i prediction = half_pel_row(load16, reference + y * reference_stride, reference_stride, fx, fy);
    sum += horizontal_sum(_mm_sad_epu8(load16(source + y * source_stride), prediction));
    if (sum > limit) return sum;
  }
  return sum;
}

}  // namespace

void init_mc_sse2(DspTable* table) {
  table->put_half_pel = put_half_pel_sse2;
  table->average = average_sse2;
  table->sad_16x16 = sad_16x16_sse2;
  table->sad_half_pel_16x16 = sad_half_pel_16x16_sse2;
}

}  // namespace svc::codec::dsp
