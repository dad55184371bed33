// Plain motion-compensation kernels: MPEG-2 half-pel interpolation, bi-prediction
// averaging and SADs (codec/motion_compensation.h defines the arithmetic).
#include <algorithm>
#include <cstdlib>

#include "codec/dsp/dsp_init.h"

namespace svc::codec::dsp {

void put_half_pel_c(const uint8_t* window, ptrdiff_t window_stride, int width, int height, int fx, int fy,
                    uint8_t* out, ptrdiff_t out_stride) {
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = window + y * window_stride;
    const uint8_t* below = row + window_stride;
    uint8_t* dst = out + y * out_stride;
    if (fx == 0 && fy == 0) {
      std::copy_n(row, width, dst);
    } else if (fy == 0) {
      for (int x = 0; x < width; ++x) dst[x] = static_cast<uint8_t>((row[x] + row[x + 1] + 1) >> 1);
    } else if (fx == 0) {
      for (int x = 0; x < width; ++x) dst[x] = static_cast<uint8_t>((row[x] + below[x] + 1) >> 1);
    } else {
      for (int x = 0; x < width; ++x) {
        dst[x] = static_cast<uint8_t>((row[x] + row[x + 1] + below[x] + below[x + 1] + 2) >> 2);
      }
    }
  }
}

namespace {

void average_c(const uint8_t* a, const uint8_t* b, int count, uint8_t* out) {
  for (int i = 0; i < count; ++i) out[i] = static_cast<uint8_t>((a[i] + b[i] + 1) >> 1);
}

int sad_16x16_c(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  int sum = 0;
  for (int y = 0; y < 16; ++y) {
    const uint8_t* row = source + y * source_stride;
    const uint8_t* pred = prediction + 16 * y;
    for (int x = 0; x < 16; ++x) sum += std::abs(row[x] - pred[x]);
  }
  return sum;
}

int sad_half_pel_16x16_c(const uint8_t* reference, ptrdiff_t reference_stride, int fx, int fy,
                         const uint8_t* source, ptrdiff_t source_stride, int limit) {
  int sum = 0;
  for (int y = 0; y < 16; ++y) {
    uint8_t prediction[16];
    put_half_pel_c(reference + y * reference_stride, reference_stride, 16, 1, fx, fy, prediction, 16);
    const uint8_t* src = source + y * source_stride;
    for (int x = 0; x < 16; ++x) sum += std::abs(src[x] - prediction[x]);
    if (sum > limit) return sum;  // the search only needs to know it lost
  }
  return sum;
}

}  // namespace

void init_mc_c(DspTable* table) {
  table->put_half_pel = put_half_pel_c;
  table->average = average_c;
  table->sad_16x16 = sad_16x16_c;
  table->sad_half_pel_16x16 = sad_half_pel_16x16_c;
}

}  // namespace svc::codec::dsp
