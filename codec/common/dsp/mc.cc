// Plain motion-compensation kernels: the separable 8-tap interpolation to 14-bit
// intermediates, their rounding to samples (single and bidirectional) and the SADs
// (docs/codec.md, section 10.1, defines the arithmetic).
#include <algorithm>
#include <cstdlib>

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

namespace {

int sad_16x16_c(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  int sum = 0;
  for (int y = 0; y < 16; ++y) {
    const uint8_t* row = source + y * source_stride;
    const uint8_t* pred = prediction + 16 * y;
    for (int x = 0; x < 16; ++x) sum += std::abs(row[x] - pred[x]);
  }
  return sum;
}

int sad_average_c(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* a, const uint8_t* b,
                  ptrdiff_t reference_stride, int width, int height) {
  int sum = 0;
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = source + y * source_stride;
    const uint8_t* first = a + y * reference_stride;
    const uint8_t* second = b + y * reference_stride;
    for (int x = 0; x < width; ++x) sum += std::abs(row[x] - ((first[x] + second[x] + 1) >> 1));
  }
  return sum;
}

}  // namespace

void init_mc_c(DspTable* table) {
  table->sad_average = sad_average_c;
  table->interpolate_8tap = interpolate_8tap_c;
  table->put_intermediate = put_intermediate_c;
  table->average_intermediate = average_intermediate_c;
  table->sad_16x16 = sad_16x16_c;
}

}  // namespace svc::codec::dsp
