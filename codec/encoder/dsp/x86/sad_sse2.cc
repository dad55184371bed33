// SPDX-License-Identifier: BSD-2-Clause
// SSE2 SADs of the encoder's motion search: psadbw against a packed prediction and
// against the pavgb average of two blocks, each equal to its plain kernel in sad.cc bit
// for bit.
#include <emmintrin.h>

#include "codec/common/dsp/x86/target.h"
#include "codec/encoder/dsp/encoder_dsp_init.h"

SVC_TARGET_BEGIN("sse2")

namespace svc::codec::dsp {
namespace {

inline __m128i load16(const uint8_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }

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

int sad_average_sse2(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* a, const uint8_t* b,
                     ptrdiff_t reference_stride, int width, int height) {
  __m128i sum = _mm_setzero_si128();
  if (width == 16) {
    for (int y = 0; y < height; ++y) {
      const __m128i average = _mm_avg_epu8(load16(a + y * reference_stride), load16(b + y * reference_stride));
      sum = _mm_add_epi64(sum, _mm_sad_epu8(load16(source + y * source_stride), average));
    }
    return horizontal_sum(sum);
  }
  auto load8 = [](const uint8_t* p) { return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)); };
  for (int y = 0; y < height; ++y) {
    const __m128i average = _mm_avg_epu8(load8(a + y * reference_stride), load8(b + y * reference_stride));
    sum = _mm_add_epi64(sum, _mm_sad_epu8(load8(source + y * source_stride), average));
  }
  return _mm_cvtsi128_si32(sum);
}

}  // namespace

void init_sad_sse2(EncoderDspTable* table) {
  table->sad_average = sad_average_sse2;
  table->sad_16x16 = sad_16x16_sse2;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
