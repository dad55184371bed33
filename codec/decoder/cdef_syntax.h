// SPDX-License-Identifier: BSD-2-Clause
// Reading of the CDEF syntax (docs/codec.md section 5.8.2) at the end of a frame's
// range-coded data. Every bit pattern reads as valid parameters; truncation shows in the
// decoder's truncated().
#pragma once

#include "codec/common/cdef.h"
#include "codec/decoder/range_decoder.h"

namespace svc::codec {

// Reads the presets and the choice of each of the units_x x units_y filter units.
void read_cdef_syntax(RangeDecoder& decoder, int units_x, int units_y, CdefParams* params);

}  // namespace svc::codec
