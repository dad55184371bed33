// SPDX-License-Identifier: BSD-2-Clause
// AVX2 YCbCr -> RGB, RGBA and BGRA rows: the SSE2 arithmetic of color_sse2.h (the plain
// formulas with the 17-bit constants split for pmaddwd) on 32 pixels at once, each
// 128-bit half one group of 16 pixels and their 8 chroma samples; RGB takes the SSE4.1
// variant's pshufb interleave within each half, RGBA and BGRA two rounds of unpacking. A
// last group of 16 takes the 128-bit code, fewer the plain kernel. Equal to the plain
// kernels bit for bit (tests/checkkernels).
#include <immintrin.h>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("avx2")

#include "codec/common/dsp/x86/color_sse2.h"

namespace svc::codec::dsp {
namespace {

// pshufb masks picking, for output bytes 16 j .. 16 j + 15 of a group of 16 pixels (byte
// k is channel k % 3 of pixel k / 3), the bytes of channel c's plane; -128 leaves zero.
// Both 128-bit halves alike.
struct InterleaveMasks {
  alignas(32) int8_t bytes[3][3][32];  // [output vector][channel]
};
constexpr InterleaveMasks kInterleaveMasks = [] {
  InterleaveMasks masks{};
  for (int j = 0; j < 3; ++j) {
    for (int c = 0; c < 3; ++c) {
      for (int i = 0; i < 32; ++i) {
        const int k = 16 * j + i % 16;
        masks.bytes[j][c][i] = static_cast<int8_t>(k % 3 == c ? k / 3 : -128);
      }
    }
  }
  return masks;
}();

inline __m256i mask(int j, int c) {
  return _mm256_load_si256(reinterpret_cast<const __m256i*>(kInterleaveMasks.bytes[j][c]));
}

inline __m256i rounded_shift(__m256i products) {
  return _mm256_srai_epi32(_mm256_add_epi32(products, _mm256_set1_epi32(32768)), 16);
}

inline __m256i term(__m256i low_pairs, __m256i high_pairs, __m256i weights) {
  return _mm256_packs_epi32(rounded_shift(_mm256_madd_epi16(low_pairs, weights)),
                            rounded_shift(_mm256_madd_epi16(high_pairs, weights)));
}

// Chroma terms of 16 chroma samples (one lane each), as chroma_terms in color_sse2.h.
struct ChromaTerms32 {
  __m256i r, g, b;
};
inline ChromaTerms32 chroma_terms_16(const uint8_t* cb, const uint8_t* cr) {
  const __m256i bias = _mm256_set1_epi16(128);
  const __m256i dcb =
      _mm256_sub_epi16(_mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(cb))), bias);
  const __m256i dcr =
      _mm256_sub_epi16(_mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(cr))), bias);
  // Per half: (dcb, dcr) pairs of chroma 0..3 and 4..7 of its 8, which packs puts back in order.
  const __m256i low = _mm256_unpacklo_epi16(dcb, dcr), high = _mm256_unpackhi_epi16(dcb, dcr);
  const __m256i r = _mm256_add_epi16(term(low, high, _mm256_set1_epi32(26345 << 16)), dcr);
  const __m256i g = _mm256_sub_epi16(term(low, high, _mm256_set1_epi32((18734 << 16) | (-22554 & 0xffff))), dcr);
  const __m256i b =
      _mm256_add_epi16(term(low, high, _mm256_set1_epi32(-14942 & 0xffff)), _mm256_add_epi16(dcb, dcb));
  return {r, g, b};
}

// Adds a chroma term (one per two pixels) to the luma samples and clamps to bytes.
inline __m256i channel(__m256i y, __m256i chroma) {
  const __m256i zero = _mm256_setzero_si256();
  const __m256i low = _mm256_add_epi16(_mm256_unpacklo_epi8(y, zero), _mm256_unpacklo_epi16(chroma, chroma));
  const __m256i high = _mm256_add_epi16(_mm256_unpackhi_epi8(y, zero), _mm256_unpackhi_epi16(chroma, chroma));
  return _mm256_packus_epi16(low, high);
}

// R, G and B of 32 pixels at y[0..31] with chroma cb[0..15], cr[0..15]; each 128-bit half
// holds 16 pixels in order.
struct RgbPlanes32 {
  __m256i r, g, b;
};
inline RgbPlanes32 ycbcr_to_rgb_32(const uint8_t* y, const uint8_t* cb, const uint8_t* cr) {
  const ChromaTerms32 terms = chroma_terms_16(cb, cr);
  const __m256i luma = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(y));
  return {channel(luma, terms.r), channel(luma, terms.g), channel(luma, terms.b)};
}

// Packed RGB of 32 pixels: per half, the three output vectors of its 16 pixels.
void store_rgb_32(const RgbPlanes32& planes, uint8_t* rgb) {
  __m256i packed[3];  // per half: output vector j of pixels 0..15 (16..31)
  for (int j = 0; j < 3; ++j) {
    packed[j] = _mm256_or_si256(_mm256_or_si256(_mm256_shuffle_epi8(planes.r, mask(j, 0)),
                                                _mm256_shuffle_epi8(planes.g, mask(j, 1))),
                                _mm256_shuffle_epi8(planes.b, mask(j, 2)));
  }
  auto* out = reinterpret_cast<__m256i*>(rgb);
  _mm256_storeu_si256(out, _mm256_permute2x128_si256(packed[0], packed[1], 0x20));
  _mm256_storeu_si256(out + 1, _mm256_permute2x128_si256(packed[2], packed[0], 0x30));
  _mm256_storeu_si256(out + 2, _mm256_permute2x128_si256(packed[1], packed[2], 0x31));
}

// Packed RGB of 16 pixels (128-bit).
void store_rgb_16(const RgbPlanes& planes, uint8_t* rgb) {
  for (int j = 0; j < 3; ++j) {
    auto picked = [&](__m128i plane, int c) { return _mm_shuffle_epi8(plane, _mm256_castsi256_si128(mask(j, c))); };
    const __m128i packed =
        _mm_or_si128(_mm_or_si128(picked(planes.r, 0), picked(planes.g, 1)), picked(planes.b, 2));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(rgb + 16 * j), packed);
  }
}

// 32 pixels of 4 bytes: first, second, third, 255. The in-lane unpacks leave pixels 0..3
// and 16..19 in one vector (and so on), which the cross-lane permutes put back in order.
void store_4_byte_32(__m256i first, __m256i second, __m256i third, uint8_t* out) {
  const __m256i alpha = _mm256_set1_epi8(-1);
  const __m256i low_12 = _mm256_unpacklo_epi8(first, second), high_12 = _mm256_unpackhi_epi8(first, second);
  const __m256i low_3a = _mm256_unpacklo_epi8(third, alpha), high_3a = _mm256_unpackhi_epi8(third, alpha);
  const __m256i p0 = _mm256_unpacklo_epi16(low_12, low_3a);    // pixels 0..3, 16..19
  const __m256i p1 = _mm256_unpackhi_epi16(low_12, low_3a);    // 4..7, 20..23
  const __m256i p2 = _mm256_unpacklo_epi16(high_12, high_3a);  // 8..11, 24..27
  const __m256i p3 = _mm256_unpackhi_epi16(high_12, high_3a);  // 12..15, 28..31
  auto* vectors = reinterpret_cast<__m256i*>(out);
  _mm256_storeu_si256(vectors, _mm256_permute2x128_si256(p0, p1, 0x20));
  _mm256_storeu_si256(vectors + 1, _mm256_permute2x128_si256(p2, p3, 0x20));
  _mm256_storeu_si256(vectors + 2, _mm256_permute2x128_si256(p0, p1, 0x31));
  _mm256_storeu_si256(vectors + 3, _mm256_permute2x128_si256(p2, p3, 0x31));
}

void store_rgba_32(const RgbPlanes32& planes, uint8_t* rgba) {
  store_4_byte_32(planes.r, planes.g, planes.b, rgba);
}
void store_bgra_32(const RgbPlanes32& planes, uint8_t* bgra) {
  store_4_byte_32(planes.b, planes.g, planes.r, bgra);
}

using PixelStore32 = void (*)(const RgbPlanes32& planes, uint8_t* out);

// A row of kBytes-byte pixels: groups of 32, then one of 16, converted here and written by
// store32 and store16, the rest by the plain kernel `tail` of the same layout.
template <PixelStore32 store32, PixelStore16 store16, int kBytes, ColorRow tail>
void ycbcr_row_32(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* out) {
  int x = 0;
  for (; x + 32 <= width; x += 32) store32(ycbcr_to_rgb_32(y + x, cb + x / 2, cr + x / 2), out + kBytes * x);
  if (x + 16 <= width) {
    store16(ycbcr_to_rgb_16(y + x, cb + x / 2, cr + x / 2), out + kBytes * x);
    x += 16;
  }
  if (x < width) tail(y + x, cb + x / 2, cr + x / 2, width - x, out + kBytes * x);  // x is even
}

}  // namespace

void init_color_avx2(DspTable* table) {
  table->ycbcr_to_rgb_row = ycbcr_row_32<store_rgb_32, store_rgb_16, 3, ycbcr_to_rgb_row_c>;
  table->ycbcr_to_rgba_row = ycbcr_row_32<store_rgba_32, store_rgba_16, 4, ycbcr_to_rgba_row_c>;
  table->ycbcr_to_bgra_row = ycbcr_row_32<store_bgra_32, store_bgra_16, 4, ycbcr_to_bgra_row_c>;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
