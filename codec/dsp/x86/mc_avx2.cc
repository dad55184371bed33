// AVX2 motion-search SAD: two rows of the 16x16 block per 256-bit operation, with the
// SSE2 kernel's exact half-pel averages (mc_sse2.cc). It checks the limit every two
// rows, so above the limit it may return a larger partial sum than the plain kernel;
// the contract (dsp.h) asks only for some value above the limit there.
#include <immintrin.h>

#include "codec/dsp/dsp_init.h"

#pragma GCC target("avx2")

namespace svc::codec::dsp {
namespace {

// Rows p and p + stride in the low and high 128-bit lanes.
inline __m256i load_two_rows(const uint8_t* p, ptrdiff_t stride) {
  const __m128i low = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
  const __m128i high = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + stride));
  return _mm256_inserti128_si256(_mm256_castsi128_si256(low), high, 1);
}

// (a + b + c + d + 2) >> 2 per byte, exactly (see average4_epu8 in mc_sse2.cc).
inline __m256i average4_epu8(__m256i a, __m256i b, __m256i c, __m256i d) {
  const __m256i ab = _mm256_avg_epu8(a, b), cd = _mm256_avg_epu8(c, d);
  const __m256i odd = _mm256_or_si256(_mm256_xor_si256(a, b), _mm256_xor_si256(c, d));
  const __m256i excess = _mm256_and_si256(_mm256_and_si256(odd, _mm256_xor_si256(ab, cd)), _mm256_set1_epi8(1));
  return _mm256_sub_epi8(_mm256_avg_epu8(ab, cd), excess);
}

inline __m256i half_pel_two_rows(const uint8_t* row, ptrdiff_t stride, int fx, int fy) {
  const __m256i a = load_two_rows(row, stride);
  if (fy == 0) return fx == 0 ? a : _mm256_avg_epu8(a, load_two_rows(row + 1, stride));
  const uint8_t* below = row + stride;
  if (fx == 0) return _mm256_avg_epu8(a, load_two_rows(below, stride));
  return average4_epu8(a, load_two_rows(row + 1, stride), load_two_rows(below, stride),
                       load_two_rows(below + 1, stride));
}

inline int horizontal_sum(__m256i sad) {
  const __m128i folded = _mm_add_epi64(_mm256_castsi256_si128(sad), _mm256_extracti128_si256(sad, 1));
  return _mm_cvtsi128_si32(folded) + _mm_cvtsi128_si32(_mm_srli_si128(folded, 8));
}

int sad_half_pel_16x16_avx2(const uint8_t* reference, ptrdiff_t reference_stride, int fx, int fy,
                            const uint8_t* source, ptrdiff_t source_stride, int limit) {
  __m256i sum = _mm256_setzero_si256();
  for (int y = 0; y < 16; y += 2) {
    const __m256i prediction = half_pel_two_rows(reference + y * reference_stride, reference_stride, fx, fy);
    sum = _mm256_add_epi64(sum,
                           _mm256_sad_epu8(load_two_rows(source + y * source_stride, source_stride), prediction));
    if ((y & 6) == 6) {  // every 8 rows: the horizontal sum costs about as much as a row
      const int total = horizontal_sum(sum);
      if (total > limit) return total;
    }
  }
  return horizontal_sum(sum);
}

int sad_16x16_avx2(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  __m256i sum = _mm256_setzero_si256();
  for (int y = 0; y < 16; y += 2) {
    const __m256i packed = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(prediction + 16 * y));
    sum = _mm256_add_epi64(sum, _mm256_sad_epu8(load_two_rows(source + y * source_stride, source_stride), packed));
  }
  return horizontal_sum(sum);
}

}  // namespace

void init_mc_avx2(DspTable* table) {
  table->sad_16x16 = sad_16x16_avx2;
  table->sad_half_pel_16x16 = sad_half_pel_16x16_avx2;
}

}  // namespace svc::codec::dsp
