// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/cfl.h"

#include <algorithm>

#include "codec/common/dsp/dsp.h"

namespace svc::codec {

void cfl_luma_ac(const uint8_t* luma, ptrdiff_t stride, int x0, int y0, int16_t* ac) {
  dsp::get_dsp().cfl_luma_ac_8x8(luma + 2 * y0 * stride + 2 * x0, stride, ac);
}

int dc_prediction_8x8(const uint8_t* edge) {
  uint8_t prediction[64];
  dsp::get_dsp().intra_predict[size_index(TransformSize::k8x8)](edge, kDcMode, prediction);
  return prediction[0];
}

void predict_cfl(const int16_t* ac, int dc, int alpha, uint8_t* out) {
  dsp::get_dsp().cfl_predict_8x8(ac, dc, std::clamp(alpha, -kCflMaxAlpha, kCflMaxAlpha), out);
}

}  // namespace svc::codec
