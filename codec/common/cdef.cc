// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/cdef.h"

#include <algorithm>
#include <vector>

#include "codec/common/dsp/dsp.h"

namespace svc::codec {
namespace {

using namespace cdef;

void filter_block(const WidenedPlanes& input, int p, const PlaneView& output, int x0, int y0, int size,
                  const dsp::CdefTaps& taps) {
  if (taps.primary == 0 && taps.secondary == 0) return;
  dsp::get_dsp().cdef_filter_block(input.at(p, x0, y0), input.stride(p),
                                   output.data + static_cast<ptrdiff_t>(y0) * output.stride + x0, output.stride,
                                   size, taps);
}

// Filters every block of `planes` in place from their unfiltered, widened `input`. The
// direction search reads the block in `planes`: no block is written before its own turn.
void filter_frame(const CdefParams& params, int qindex, std::span<const uint8_t> skip, const WidenedPlanes& input,
                  const std::array<PlaneView, 3>& planes) {
  const int blocks_x = planes[0].width / 8, blocks_y = planes[0].height / 8;
  const int units_x = cdef_units(planes[0].width);
  const int damping = damping_of(qindex);
  for (int by = 0; by < blocks_y; ++by) {
    for (int bx = 0; bx < blocks_x; ++bx) {
      const size_t block = static_cast<size_t>(by) * blocks_x + bx;
      const int preset = params.unit_presets[static_cast<size_t>(by / 8) * units_x + bx / 8];
      if (preset == 0 || (!skip.empty() && skip[block] != 0)) continue;
      const CdefStrength& strength = params.presets[preset - 1];
      const int secondary = secondary_of(strength.secondary_code);
      // Without primary taps the direction is 0 and the contrast unused: no search.
      int32_t variance = 0;
      const int luma_direction =
          strength.primary == 0
              ? 0
              : dsp::get_dsp().cdef_direction_8x8(planes[0].data +
                                                      static_cast<ptrdiff_t>(8 * by) * planes[0].stride + 8 * bx,
                                                  planes[0].stride, &variance);
      filter_block(input, 0, planes[0], 8 * bx, 8 * by, 8,
                   dsp::CdefTaps{adjusted_primary(strength.primary, variance), secondary, luma_direction, damping});
      for (int p = 1; p < 3; ++p) {
        filter_block(input, p, planes[p], 4 * bx, 4 * by, 4,
                     dsp::CdefTaps{strength.primary, secondary, luma_direction, damping - 1});
      }
    }
  }
}

bool params_fit(const CdefParams& params, int units) {
  if (params.presets.empty() || params.presets.size() > kCdefMaxPresets) return false;
  if (params.unit_presets.size() != static_cast<size_t>(units)) return false;
  return std::all_of(params.unit_presets.begin(), params.unit_presets.end(),
                     [&](uint8_t preset) { return preset <= params.presets.size(); });
}

}  // namespace

int cdef_units(int samples) { return std::max(0, (samples + kCdefUnitSize - 1) / kCdefUnitSize); }

void cdef_frame(const CdefParams& params, int qindex, std::span<const uint8_t> skip,
                const std::array<PlaneView, 3>& planes) {
  if (!planes_fit(planes)) return;
  if (!params_fit(params, cdef_units(planes[0].width) * cdef_units(planes[0].height))) return;
  const size_t blocks = static_cast<size_t>(planes[0].width / 8) * (planes[0].height / 8);
  if (!skip.empty() && skip.size() != blocks) return;
  const WidenedPlanes input(planes);
  filter_frame(params, qindex, skip, input, planes);
}

}  // namespace svc::codec
