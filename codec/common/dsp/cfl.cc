// SPDX-License-Identifier: BSD-2-Clause
// Plain chroma-from-luma kernels (docs/codec.md 3.3): the luma of an 8x8 chroma block
// averaged 2x2 to chroma resolution minus its mean, and the prediction that scales it.
#include <algorithm>

#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

void cfl_luma_ac_8x8_c(const uint8_t* luma, ptrdiff_t stride, int16_t* ac) {
  int sum = 0;
  for (int y = 0; y < 8; ++y) {
    const uint8_t* top = luma + 2 * y * stride;
    const uint8_t* bottom = top + stride;
    for (int x = 0; x < 8; ++x) {
      const int s = top[2 * x] + top[2 * x + 1] + bottom[2 * x] + bottom[2 * x + 1];
      ac[8 * y + x] = static_cast<int16_t>(s);
      sum += s;
    }
  }
  const int mean = (sum + 32) >> 6;
  for (int i = 0; i < 64; ++i) ac[i] = static_cast<int16_t>(ac[i] - mean);
}

void cfl_predict_8x8_c(const int16_t* ac, int dc, int alpha, uint8_t* out) {
  for (int i = 0; i < 64; ++i) out[i] = static_cast<uint8_t>(std::clamp(dc + ((alpha * ac[i] + 16) >> 5), 0, 255));
}

}  // namespace

void init_cfl_c(DspTable* table) {
  table->cfl_luma_ac_8x8 = cfl_luma_ac_8x8_c;
  table->cfl_predict_8x8 = cfl_predict_8x8_c;
}

}  // namespace svc::codec::dsp
