// SPDX-License-Identifier: BSD-2-Clause
#include "codec/decoder/cdef_syntax.h"

namespace svc::codec {

using namespace cdef;

void read_cdef_syntax(RangeDecoder& decoder, int units_x, int units_y, CdefParams* params) {
  int count = 1;
  for (int bit = 0; bit < 2; ++bit) count += decoder.decode_bypass() << (1 - bit);
  params->presets.assign(static_cast<size_t>(count), CdefStrength{});
  for (CdefStrength& strength : params->presets) {
    int primary = 0, secondary = 0;
    for (int bit = 0; bit < 4; ++bit) primary = (primary << 1) | decoder.decode_bypass();
    for (int bit = 0; bit < 2; ++bit) secondary = (secondary << 1) | decoder.decode_bypass();
    strength = CdefStrength{static_cast<uint8_t>(primary), static_cast<uint8_t>(secondary)};
  }
  params->unit_presets.assign(static_cast<size_t>(units_x) * units_y, 0);
  CdefContexts contexts;
  for (int uy = 0; uy < units_y; ++uy) {
    for (int ux = 0; ux < units_x; ++ux) {
      if (!decoder.decode(contexts.unit_on[unit_on_context(params->unit_presets, units_x, ux, uy)])) continue;
      int preset = 1;
      while (preset < count && decoder.decode(contexts.preset_more[preset - 1])) ++preset;
      params->unit_presets[static_cast<size_t>(uy) * units_x + ux] = static_cast<uint8_t>(preset);
    }
  }
}

}  // namespace svc::codec
