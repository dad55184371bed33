// Plain warped-prediction kernel: bilinear weighting in 1/16 pel of four gathered taps
// (codec/warp_prediction.h defines the arithmetic).
#include "codec/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

void warp_row_c(const uint8_t* plane, ptrdiff_t stride, const WarpRow& r, uint8_t* out) {
  const int round = 1 << (r.shift - 1);
  int sx = r.sx, sy = r.sy;
  for (int u = 0; u < r.count; ++u, sx += r.step_x, sy += r.step_y) {
    const int X = r.x16 + 16 * u + ((sx + round) >> r.shift), Y = r.y16 + ((sy + round) >> r.shift);
    const uint8_t* p = plane + (Y >> 4) * stride + (X >> 4);
    const int fx = X & 15, fy = Y & 15;
    out[u] = static_cast<uint8_t>(((16 - fx) * (16 - fy) * p[0] + fx * (16 - fy) * p[1] +
                                   (16 - fx) * fy * p[stride] + fx * fy * p[stride + 1] + 128) >>
                                  8);
  }
}

}  // namespace

void init_warp_c(DspTable* table) { table->warp_row = warp_row_c; }

}  // namespace svc::codec::dsp
