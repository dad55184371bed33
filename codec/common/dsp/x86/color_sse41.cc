// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 color rows. pshufb (SSSE3, which every SSE4.1 processor has) moves between
// packed RGB and planes; the arithmetic is the plain kernels' integer formulas
// (color_formulas.h) on pmaddwd, with constants that do not fit 16 bits split in two.
// YCbCr -> RGB uses the SSE2 arithmetic of color_sse2.h. RGBA and BGRA keep the SSE2
// rows: unpacking already interleaves 4-byte pixels, so pshufb would not make them faster.
#include <emmintrin.h>
#include <tmmintrin.h>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse4.1")

#include "codec/common/dsp/x86/color_sse2.h"

namespace svc::codec::dsp {
namespace {

// Shuffle masks gathering channel c of 16 packed RGB pixels from the 16-byte vector j of
// their 48 bytes; -128 leaves zero.
struct DeinterleaveMasks {
  __m128i mask[3][3];  // [input vector][channel]
  DeinterleaveMasks() {
    for (int j = 0; j < 3; ++j) {
      for (int c = 0; c < 3; ++c) {
        alignas(16) int8_t bytes[16];
        for (int i = 0; i < 16; ++i) {
          const int k = 3 * i + c - 16 * j;
          bytes[i] = static_cast<int8_t>(k >= 0 && k < 16 ? k : -128);
        }
        mask[j][c] = _mm_load_si128(reinterpret_cast<const __m128i*>(bytes));
      }
    }
  }
};

struct Planes {
  __m128i channel[3];  // r, g, b of 16 pixels
};

Planes deinterleave_16(const uint8_t* rgb) {
  static const DeinterleaveMasks masks;
  __m128i in[3];
  for (int j = 0; j < 3; ++j) in[j] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(rgb + 16 * j));
  Planes planes;
  for (int c = 0; c < 3; ++c) {
    planes.channel[c] = _mm_or_si128(_mm_or_si128(_mm_shuffle_epi8(in[0], masks.mask[0][c]),
                                                  _mm_shuffle_epi8(in[1], masks.mask[1][c])),
                                     _mm_shuffle_epi8(in[2], masks.mask[2][c]));
  }
  return planes;
}

inline __m128i pairs(int first, int second) {
  return _mm_set1_epi32(static_cast<int>((static_cast<uint32_t>(second) << 16) | static_cast<uint16_t>(first)));
}

// Y of 8 pixels (16-bit r, g, b lanes): (19595 r + 38470 g + 7471 b + 32768) >> 16 with
// 38470 = 2 x 19235; never outside 0..255 (the weights sum to 65536).
__m128i luma_8(__m128i r, __m128i g, __m128i b) {
  const __m128i round = _mm_set1_epi32(32768);
  const __m128i rg = pairs(19595, 19235), bg = pairs(7471, 19235);
  const __m128i low = _mm_add_epi32(_mm_add_epi32(_mm_madd_epi16(_mm_unpacklo_epi16(r, g), rg),
                                                  _mm_madd_epi16(_mm_unpacklo_epi16(b, g), bg)),
                                    round);
  const __m128i high = _mm_add_epi32(_mm_add_epi32(_mm_madd_epi16(_mm_unpackhi_epi16(r, g), rg),
                                                   _mm_madd_epi16(_mm_unpackhi_epi16(b, g), bg)),
                                     round);
  return _mm_packs_epi32(_mm_srai_epi32(low, 16), _mm_srai_epi32(high, 16));
}

void rgb_to_luma_row_sse41(const uint8_t* rgb, int width, uint8_t* y) {
  const __m128i zero = _mm_setzero_si128();
  int x = 0;
  for (; x + 16 <= width; x += 16) {
    const Planes p = deinterleave_16(rgb + 3 * x);
    const __m128i low = luma_8(_mm_unpacklo_epi8(p.channel[0], zero), _mm_unpacklo_epi8(p.channel[1], zero),
                               _mm_unpacklo_epi8(p.channel[2], zero));
    const __m128i high = luma_8(_mm_unpackhi_epi8(p.channel[0], zero), _mm_unpackhi_epi8(p.channel[1], zero),
                                _mm_unpackhi_epi8(p.channel[2], zero));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(y + x), _mm_packus_epi16(low, high));
  }
  if (x < width) rgb_to_luma_row_c(rgb + 3 * x, width - x, y + x);
}

// One chroma channel of 8 samples from the 2x2 sums (16-bit) of r, g, b:
// clamp((wr r + wg g + wb b + 2^17 + (128 << 18)) >> 18), weights given as two pairs
// (first * a + second * b) so that 32768 can be written 16384 + 16384.
__m128i chroma_8(__m128i a0, __m128i a1, __m128i w0, __m128i b0, __m128i b1, __m128i w1) {
  const __m128i bias = _mm_set1_epi32((1 << 17) + (128 << 18));
  const __m128i low = _mm_add_epi32(_mm_add_epi32(_mm_madd_epi16(_mm_unpacklo_epi16(a0, a1), w0),
                                                  _mm_madd_epi16(_mm_unpacklo_epi16(b0, b1), w1)),
                                    bias);
  const __m128i high = _mm_add_epi32(_mm_add_epi32(_mm_madd_epi16(_mm_unpackhi_epi16(a0, a1), w0),
                                                   _mm_madd_epi16(_mm_unpackhi_epi16(b0, b1), w1)),
                                     bias);
  const __m128i words = _mm_packs_epi32(_mm_srai_epi32(low, 18), _mm_srai_epi32(high, 18));
  return _mm_packus_epi16(words, words);  // the clamp to 0..255, in the low 8 bytes
}

void rgb_to_chroma_row_sse41(const uint8_t* row0, const uint8_t* row1, int width, uint8_t* cb, uint8_t* cr) {
  const __m128i ones = _mm_set1_epi8(1);
  int x = 0;
  for (; x + 16 <= width; x += 16) {
    const Planes p0 = deinterleave_16(row0 + 3 * x), p1 = deinterleave_16(row1 + 3 * x);
    __m128i sum[3];  // 2x2 sums per channel, 8 lanes
    for (int c = 0; c < 3; ++c) {
      sum[c] = _mm_add_epi16(_mm_maddubs_epi16(p0.channel[c], ones), _mm_maddubs_epi16(p1.channel[c], ones));
    }
    const __m128i r = sum[0], g = sum[1], b = sum[2];
    const __m128i out_cb = chroma_8(r, g, pairs(-11059, -21709), b, b, pairs(16384, 16384));
    const __m128i out_cr = chroma_8(r, r, pairs(16384, 16384), g, b, pairs(-27439, -5329));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(cb + x / 2), out_cb);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(cr + x / 2), out_cr);
  }
  if (x < width) rgb_to_chroma_row_c(row0 + 3 * x, row1 + 3 * x, width - x, cb + x / 2, cr + x / 2);  // x is even
}

// Shuffle masks picking, for output bytes 16 j .. 16 j + 15 (byte k is channel k % 3 of
// pixel k / 3), the bytes of one channel's plane; -128 leaves zero. Constant data rather
// than a static built on first use, so that storing each group of 16 pixels does not
// test a guard.
struct InterleaveMasks {
  alignas(16) int8_t bytes[3][3][16];  // [output vector][channel]
};
constexpr InterleaveMasks kInterleaveMasks = [] {
  InterleaveMasks masks{};
  for (int j = 0; j < 3; ++j) {
    for (int c = 0; c < 3; ++c) {
      for (int i = 0; i < 16; ++i) {
        const int k = 16 * j + i;
        masks.bytes[j][c][i] = static_cast<int8_t>(k % 3 == c ? k / 3 : -128);
      }
    }
  }
  return masks;
}();

inline __m128i interleave_mask(int j, int c) {
  return _mm_load_si128(reinterpret_cast<const __m128i*>(kInterleaveMasks.bytes[j][c]));
}

void store_rgb_16(const RgbPlanes& planes, uint8_t* rgb) {
  for (int j = 0; j < 3; ++j) {
    const __m128i packed = _mm_or_si128(_mm_or_si128(_mm_shuffle_epi8(planes.r, interleave_mask(j, 0)),
                                                     _mm_shuffle_epi8(planes.g, interleave_mask(j, 1))),
                                        _mm_shuffle_epi8(planes.b, interleave_mask(j, 2)));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(rgb + 16 * j), packed);
  }
}

}  // namespace

void init_color_sse41(DspTable* table) {
  table->rgb_to_luma_row = rgb_to_luma_row_sse41;
  table->rgb_to_chroma_row = rgb_to_chroma_row_sse41;
  table->ycbcr_to_rgb_row = ycbcr_row_16<store_rgb_16, 3, ycbcr_to_rgb_row_c>;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
