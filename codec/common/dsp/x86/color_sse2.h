// The SSE2 arithmetic of the YCbCr -> RGB row kernels, shared by the SSE2 and SSE4.1
// variants (internal linkage: each includes it under its own target). The plain
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

}  // namespace
}  // namespace svc::codec::dsp
