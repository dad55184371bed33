// SPDX-License-Identifier: BSD-2-Clause
// Plain SAD kernels of the encoder's motion search: against a packed prediction and
// against the rounded-up average of two reference blocks.
#include <cstdlib>

#include "codec/encoder/dsp/encoder_dsp_init.h"

namespace svc::codec::dsp {
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

void init_sad_c(EncoderDspTable* table) {
  table->sad_average = sad_average_c;
  table->sad_16x16 = sad_16x16_c;
}

}  // namespace svc::codec::dsp
