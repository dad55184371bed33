// SPDX-License-Identifier: BSD-2-Clause
#include "codec/encoder/sad.h"

#include <cstddef>
#include <cstdlib>

#include "codec/encoder/dsp/encoder_dsp.h"

namespace svc::codec {

int sad_16x16(const uint8_t* source, int source_stride, const uint8_t* prediction) {
  return dsp::get_encoder_dsp().sad_16x16(source, source_stride, prediction);
}

int sad_16x16_reference(const uint8_t* source, int source_stride, const uint8_t* prediction) {
  int sum = 0;
  for (int y = 0; y < 16; ++y) {
    const uint8_t* row = source + static_cast<ptrdiff_t>(y) * source_stride;
    const uint8_t* pred = prediction + 16 * y;
    int row_sum = 0;
    for (int x = 0; x < 16; ++x) row_sum += std::abs(static_cast<int>(row[x]) - static_cast<int>(pred[x]));
    sum += row_sum;
  }
  return sum;
}

int sad_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector,
                        const uint8_t* source, int source_stride, InterpolationFilter filter) {
  int16_t intermediate[256];
  uint8_t prediction[256];
  predict_macroblock_luma(reference, mb_x, mb_y, vector, intermediate, filter);
  round_prediction(intermediate, 256, prediction);
  return sad_16x16(source, source_stride, prediction);
}

}  // namespace svc::codec
