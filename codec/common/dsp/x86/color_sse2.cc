// SPDX-License-Identifier: BSD-2-Clause
// SSE2 YCbCr -> RGB, RGBA and BGRA rows (arithmetic in color_sse2.h).
#include <emmintrin.h>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse2")

#include "codec/common/dsp/x86/color_sse2.h"

namespace svc::codec::dsp {
namespace {

void store_rgb_16(const RgbPlanes& planes, uint8_t* rgb) {
  alignas(16) uint8_t r[16], g[16], b[16];
  _mm_store_si128(reinterpret_cast<__m128i*>(r), planes.r);
  _mm_store_si128(reinterpret_cast<__m128i*>(g), planes.g);
  _mm_store_si128(reinterpret_cast<__m128i*>(b), planes.b);
  for (int i = 0; i < 16; ++i) {  // SSE2 has no byte shuffle to interleave with
    rgb[3 * i] = r[i];
    rgb[3 * i + 1] = g[i];
    rgb[3 * i + 2] = b[i];
  }
}

}  // namespace

void init_color_sse2(DspTable* table) {
  table->ycbcr_to_rgb_row = ycbcr_row_16<store_rgb_16, 3, ycbcr_to_rgb_row_c>;
  table->ycbcr_to_rgba_row = ycbcr_row_16<store_rgba_16, 4, ycbcr_to_rgba_row_c>;
  table->ycbcr_to_bgra_row = ycbcr_row_16<store_bgra_16, 4, ycbcr_to_bgra_row_c>;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
