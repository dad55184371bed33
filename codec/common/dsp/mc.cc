// SPDX-License-Identifier: BSD-2-Clause
// Plain motion-compensation kernels: the separable 8-tap interpolation to 14-bit
// intermediates and their rounding to samples (single and bidirectional) (docs/codec.md,
// section 5.6, defines the arithmetic). The encoder's SADs are in
// codec/encoder/dsp/sad.cc.
#include <algorithm>

#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {

void interpolate_8tap_c(const uint8_t* window, ptrdiff_t window_stride, int width, int height, const int8_t* h_taps,
                        const int8_t* v_taps, int16_t* out, ptrdiff_t out_stride) {
  // First pass over the height + 7 rows the second reads; fits int16 (|sum| <= 88 * 255).
  int16_t rows[(kMaxInterpolationBlock + 7) * kMaxInterpolationBlock];
  for (int y = 0; y < height + 7; ++y) {
    const uint8_t* src = window + y * window_stride;
    for (int x = 0; x < width; ++x) {
      int sum = 0;
      for (int i = 0; i < 8; ++i) sum += h_taps[i] * src[x + i];
      rows[y * width + x] = static_cast<int16_t>(sum);
    }
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      int sum = 0;
      for (int j = 0; j < 8; ++j) sum += v_taps[j] * rows[(y + j) * width + x];
      out[y * out_stride + x] = static_cast<int16_t>((sum >> 6) - kIntermediateOffset);
    }
  }
}

void put_intermediate_c(const int16_t* in, int count, uint8_t* out) {
  for (int i = 0; i < count; ++i)
    out[i] = static_cast<uint8_t>(std::clamp((in[i] + kIntermediateOffset + 32) >> 6, 0, 255));
}

void average_intermediate_c(const int16_t* a, const int16_t* b, int count, uint8_t* out) {
  for (int i = 0; i < count; ++i) {
    out[i] = static_cast<uint8_t>(std::clamp((a[i] + b[i] + 2 * kIntermediateOffset + 64) >> 7, 0, 255));
  }
}

void init_mc_c(DspTable* table) {
  table->interpolate_8tap = interpolate_8tap_c;
  table->put_intermediate = put_intermediate_c;
  table->average_intermediate = average_intermediate_c;
}

}  // namespace svc::codec::dsp
