// SPDX-License-Identifier: BSD-2-Clause
// An 8x8 transpose of 16-bit lanes, shared by the SSE4.1 intra kernels and the encoder's
// SATD (internal linkage: each includes it under its own target).
#pragma once

#include <emmintrin.h>

namespace svc::codec::dsp {
namespace {

inline void transpose_8x8_epi16(__m128i* v) {
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

}  // namespace
}  // namespace svc::codec::dsp
