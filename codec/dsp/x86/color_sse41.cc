// SSE4.1 YCbCr -> RGB rows: the SSE2 arithmetic (color_sse2.h) with pshufb (SSSE3, which
// every SSE4.1 processor has) interleaving the three planes into packed RGB.
#include <emmintrin.h>
#include <tmmintrin.h>

#include "codec/dsp/dsp_init.h"

#pragma GCC target("sse4.1")

#include "codec/dsp/x86/color_sse2.h"

namespace svc::codec::dsp {
namespace {

// Shuffle masks picking, for output bytes 16 j .. 16 j + 15 (byte k is channel k % 3 of
// pixel k / 3), the bytes of one channel's plane; -128 leaves zero.
struct InterleaveMasks {
  __m128i mask[3][3];  // [output vector][channel]
  InterleaveMasks() {
    for (int j = 0; j < 3; ++j) {
      for (int c = 0; c < 3; ++c) {
        alignas(16) int8_t bytes[16];
        for (int i = 0; i < 16; ++i) {
          const int k = 16 * j + i;
          bytes[i] = static_cast<int8_t>(k % 3 == c ? k / 3 : -128);
        }
        mask[j][c] = _mm_load_si128(reinterpret_cast<const __m128i*>(bytes));
      }
    }
  }
};

void ycbcr_to_rgb_row_sse41(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* rgb) {
  static const InterleaveMasks masks;
  int x = 0;
  for (; x + 16 <= width; x += 16) {
    const RgbPlanes planes = ycbcr_to_rgb_16(y + x, cb + x / 2, cr + x / 2);
    for (int j = 0; j < 3; ++j) {
      const __m128i packed = _mm_or_si128(_mm_or_si128(_mm_shuffle_epi8(planes.r, masks.mask[j][0]),
                                                       _mm_shuffle_epi8(planes.g, masks.mask[j][1])),
                                          _mm_shuffle_epi8(planes.b, masks.mask[j][2]));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(rgb + 3 * x + 16 * j), packed);
    }
  }
  if (x < width) ycbcr_to_rgb_row_c(y + x, cb + x / 2, cr + x / 2, width - x, rgb + 3 * x);  // x is even
}

}  // namespace

void init_color_sse41(DspTable* table) { table->ycbcr_to_rgb_row = ycbcr_to_rgb_row_sse41; }

}  // namespace svc::codec::dsp
