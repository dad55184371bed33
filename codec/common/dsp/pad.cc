// SPDX-License-Identifier: BSD-2-Clause
// Plain bilinear sampling of cube padding's border (docs/codec.md 5.7): the 2 x 2
// filter applied as two 1-D passes. With weights y_r x_c for row r, column c, the sum
// y0 (x0 p00 + x1 p01) + y1 (x0 p10 + x1 p11) is the 2-D filter's sum term for term.
#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

void pad_sample_run_c(const uint8_t* plane, ptrdiff_t stride, const uint32_t* index, const BilinearWeights* weights,
                      int count, uint8_t* out) {
  for (int k = 0; k < count; ++k) {
    const uint8_t* top = plane + index[k];
    const uint8_t* bottom = top + stride;
    const BilinearWeights& w = weights[k];
    const int upper = w.x0 * top[0] + w.x1 * top[1], lower = w.x0 * bottom[0] + w.x1 * bottom[1];
    out[k] = static_cast<uint8_t>((w.y0 * upper + w.y1 * lower + 128) >> 8);
  }
}

}  // namespace

void init_pad_c(DspTable* table) { table->pad_sample_run = pad_sample_run_c; }

}  // namespace svc::codec::dsp
