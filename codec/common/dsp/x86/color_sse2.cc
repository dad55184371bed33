// SSE2 YCbCr -> RGB rows (arithmetic in color_sse2.h).
#include <emmintrin.h>

#include "codec/common/dsp/dsp_init.h"

#pragma GCC target("sse2")

#include "codec/common/dsp/x86/color_sse2.h"

namespace svc::codec::dsp {
namespace {

void ycbcr_to_rgb_row_sse2(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* rgb) {
  int x = 0;
  for (; x + 16 <= width; x += 16) {
    const RgbPlanes planes = ycbcr_to_rgb_16(y + x, cb + x / 2, cr + x / 2);
    alignas(16) uint8_t r[16], g[16], b[16];
    _mm_store_si128(reinterpret_cast<__m128i*>(r), planes.r);
    _mm_store_si128(reinterpret_cast<__m128i*>(g), planes.g);
    _mm_store_si128(reinterpret_cast<__m128i*>(b), planes.b);
    uint8_t* out = rgb + 3 * x;
    for (int i = 0; i < 16; ++i) {  // SSE2 has no byte shuffle to interleave with
      out[3 * i] = r[i];
      out[3 * i + 1] = g[i];
      out[3 * i + 2] = b[i];
    }
  }
  if (x < width) ycbcr_to_rgb_row_c(y + x, cb + x / 2, cr + x / 2, width - x, rgb + 3 * x);  // x is even
}

}  // namespace

void init_color_sse2(DspTable* table) { table->ycbcr_to_rgb_row = ycbcr_to_rgb_row_sse2; }

}  // namespace svc::codec::dsp
