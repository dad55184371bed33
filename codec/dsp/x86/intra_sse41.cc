// SSE4.1 intra kernels. The Hadamard SATD keeps every value in 16 bits (residuals of
// at most 255 grow by 8 per 1-D pass: |value| <= 16320), so it equals the plain sum.
// Angular prediction interpolates a whole row at once with the plain kernel's integer
// formula; planar and the edge preparation run the plain code.
#include <smmintrin.h>

#include <cstring>

#include "codec/dsp/dsp_init.h"

#pragma GCC target("sse4.1")

namespace svc::codec::dsp {
namespace {

void butterflies(__m128i* v) {
  for (int span = 1; span < 8; span *= 2) {
    for (int i = 0; i < 8; i += 2 * span) {
      for (int j = i; j < i + span; ++j) {
        const __m128i a = v[j], b = v[j + span];
        v[j] = _mm_add_epi16(a, b);
        v[j + span] = _mm_sub_epi16(a, b);
      }
    }
  }
}

void transpose_8x8_epi16(__m128i* v) {
  __m128i a[8], b[8];
  for (int i = 0; i < 4; ++i) {
    a[2 * i] = _mm_unpacklo_epi16(v[2 * i], v[2 * i + 1]);
    a[2 * i + 1] = _mm_unpackhi_epi16(v[2 * i], v[2 * i + 1]);
  }
  for (int i = 0; i < 2; ++i) {
    for (int h = 0; h < 2; ++h) {
      b[4 * i + 2 * h] = _mm_unpacklo_epi32(a[4 * i + h], a[4 * i + 2 + h]);
      b[4 * i + 2 * h + 1] = _mm_unpackhi_epi32(a[4 * i + h], a[4 * i + 2 + h]);
    }
  }
  for (int i = 0; i < 4; ++i) {
    v[2 * i] = _mm_unpacklo_epi64(b[i], b[4 + i]);
    v[2 * i + 1] = _mm_unpackhi_epi64(b[i], b[4 + i]);
  }
}

int satd_8x8_sse41(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  __m128i v[8];
  for (int y = 0; y < 8; ++y) {
    const __m128i s =
        _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(source + y * source_stride)));
    const __m128i p = _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(prediction + 8 * y)));
    v[y] = _mm_sub_epi16(s, p);
  }
  butterflies(v);
  transpose_8x8_epi16(v);
  butterflies(v);
  __m128i sum = _mm_setzero_si128();
  const __m128i ones = _mm_set1_epi16(1);
  for (int y = 0; y < 8; ++y) sum = _mm_add_epi32(sum, _mm_madd_epi16(_mm_abs_epi16(v[y]), ones));
  sum = _mm_add_epi32(sum, _mm_shuffle_epi32(sum, _MM_SHUFFLE(1, 0, 3, 2)));
  sum = _mm_add_epi32(sum, _mm_shuffle_epi32(sum, _MM_SHUFFLE(2, 3, 0, 1)));
  return _mm_cvtsi128_si32(sum);
}

// One row of eight interpolated samples ((32 - f) a + f b + 16) >> 5 from ref[0..8].
__m128i interpolate_row(const uint8_t* ref, int fraction) {
  const __m128i a = _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(ref)));
  if (fraction == 0) return a;
  const __m128i b = _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(ref + 1)));
  const __m128i sum = _mm_add_epi16(_mm_mullo_epi16(a, _mm_set1_epi16(static_cast<int16_t>(32 - fraction))),
                                    _mm_mullo_epi16(b, _mm_set1_epi16(static_cast<int16_t>(fraction))));
  return _mm_srli_epi16(_mm_add_epi16(sum, _mm_set1_epi16(16)), 5);
}

void intra_predict_8x8_sse41(const uint8_t* edge, int mode, uint8_t* out) {
  if (mode < 2) {
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
}

}  // namespace

void init_intra_sse41(DspTable* table) {
  table->intra_predict_8x8 = intra_predict_8x8_sse41;
  table->satd_8x8 = satd_8x8_sse41;
}

}  // namespace svc::codec::dsp
