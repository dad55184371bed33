// SPDX-License-Identifier: BSD-2-Clause
// The SSE2 arithmetic of the YCbCr -> RGB, RGBA and BGRA row kernels, shared by the
// SSE2, SSE4.1 and AVX2 variants (internal linkage: each includes it under its own
// target); the layouts differ only in how they store a group of pixels. The plain
// kernel's 17-bit constants are split into a multiple of 65536, which passes through
// the rounding shift exactly, and a 16-bit remainder for pmaddwd: kRCr = 65536 + 26345,
// kGCr = -65536 + 18734, kBCb = 131072 - 14942. So each chroma term equals the one in
// color_formulas.h, and packus is its clamp.
#pragma once

#include <emmintrin.h>

#include <cstdint>

namespace svc::codec::dsp {
namespace {

// Chroma terms of 8 chroma samples (dcb, dcr in 16-bit lanes), each for two pixels.
struct ChromaTerms {
  __m128i r, g, b;  // 16 lanes: one per pixel
};

inline __m128i rounded_shift(__m128i products) {
  return _mm_srai_epi32(_mm_add_epi32(products, _mm_set1_epi32(32768)), 16);
}

inline __m128i term(__m128i low_pairs, __m128i high_pairs, __m128i weights) {
  return _mm_packs_epi32(rounded_shift(_mm_madd_epi16(low_pairs, weights)),
                         rounded_shift(_mm_madd_epi16(high_pairs, weights)));
}

inline ChromaTerms chroma_terms(const uint8_t* cb, const uint8_t* cr) {
  const __m128i zero = _mm_setzero_si128(), bias = _mm_set1_epi16(128);
  const __m128i dcb =
      _mm_sub_epi16(_mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(cb)), zero), bias);
  const __m128i dcr =
      _mm_sub_epi16(_mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(cr)), zero), bias);
  const __m128i low = _mm_unpacklo_epi16(dcb, dcr), high = _mm_unpackhi_epi16(dcb, dcr);  // (dcb, dcr) pairs
  const __m128i r = _mm_add_epi16(term(low, high, _mm_set1_epi32(26345 << 16)), dcr);
  const __m128i g = _mm_sub_epi16(term(low, high, _mm_set1_epi32((18734 << 16) | (-22554 & 0xffff))), dcr);
  const __m128i b = _mm_add_epi16(term(low, high, _mm_set1_epi32(-14942 & 0xffff)), _mm_add_epi16(dcb, dcb));
  return {r, g, b};
}

// Adds a chroma term (one per two pixels) to 8 luma samples per half and clamps to bytes.
inline __m128i channel(__m128i y, __m128i chroma) {
  const __m128i zero = _mm_setzero_si128();
  const __m128i low = _mm_add_epi16(_mm_unpacklo_epi8(y, zero), _mm_unpacklo_epi16(chroma, chroma));
  const __m128i high = _mm_add_epi16(_mm_unpackhi_epi8(y, zero), _mm_unpackhi_epi16(chroma, chroma));
  return _mm_packus_epi16(low, high);
}

// R, G and B of 16 pixels at y[0..15] with chroma cb[0..7], cr[0..7].
struct RgbPlanes {
  __m128i r, g, b;
};
inline RgbPlanes ycbcr_to_rgb_16(const uint8_t* y, const uint8_t* cb, const uint8_t* cr) {
  const ChromaTerms terms = chroma_terms(cb, cr);
  const __m128i luma = _mm_loadu_si128(reinterpret_cast<const __m128i*>(y));
  return {channel(luma, terms.r), channel(luma, terms.g), channel(luma, terms.b)};
}

// 16 pixels of 4 bytes: first, second, third, 255. Two rounds of unpacking interleave
// 4-byte pixels without a byte shuffle, so SSE2 needs no scalar stores here.
inline void store_4_byte_16(__m128i first, __m128i second, __m128i third, uint8_t* out) {
  const __m128i alpha = _mm_set1_epi8(-1);
  const __m128i low_12 = _mm_unpacklo_epi8(first, second), high_12 = _mm_unpackhi_epi8(first, second);
  const __m128i low_3a = _mm_unpacklo_epi8(third, alpha), high_3a = _mm_unpackhi_epi8(third, alpha);
  auto* vectors = reinterpret_cast<__m128i*>(out);
  _mm_storeu_si128(vectors, _mm_unpacklo_epi16(low_12, low_3a));
  _mm_storeu_si128(vectors + 1, _mm_unpackhi_epi16(low_12, low_3a));
  _mm_storeu_si128(vectors + 2, _mm_unpacklo_epi16(high_12, high_3a));
  _mm_storeu_si128(vectors + 3, _mm_unpackhi_epi16(high_12, high_3a));
}

inline void store_rgba_16(const RgbPlanes& planes, uint8_t* rgba) {
  store_4_byte_16(planes.r, planes.g, planes.b, rgba);
}
inline void store_bgra_16(const RgbPlanes& planes, uint8_t* bgra) {
  store_4_byte_16(planes.b, planes.g, planes.r, bgra);
}

using PixelStore16 = void (*)(const RgbPlanes& planes, uint8_t* out);
using ColorRow = void (*)(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* out);

// A row of kBytes-byte pixels: groups of 16 converted here and written by `store`, the
// rest by the plain kernel `tail` of the same layout.
template <PixelStore16 store, int kBytes, ColorRow tail>
void ycbcr_row_16(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* out) {
  int x = 0;
  for (; x + 16 <= width; x += 16) store(ycbcr_to_rgb_16(y + x, cb + x / 2, cr + x / 2), out + kBytes * x);
  if (x < width) tail(y + x, cb + x / 2, cr + x / 2, width - x, out + kBytes * x);  // x is even
}

}  // namespace
}  // namespace svc::codec::dsp
