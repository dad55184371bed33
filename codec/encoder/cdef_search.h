// SPDX-License-Identifier: BSD-2-Clause
// The encoder's CDEF decision (docs/encoder.md) and the writing of its syntax
// (docs/codec.md section 5.8.2), read by codec/decoder/cdef_syntax.h.
//
// Threading: every function is reentrant.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "codec/common/cdef.h"
#include "codec/encoder/range_encoder.h"

namespace svc::codec {

// Writes the filter's syntax. `params` must hold units_x x units_y unit entries, each at
// most its preset count.
void write_cdef_syntax(RangeEncoder& encoder, const CdefParams& params, int units_x, int units_y);

// The presets and unit choices that minimise squared error against
// `source` (visible planes, stride = width) plus lambda per estimated bit; no presets
// when the filter does not pay. `planes` is left unchanged. `every_candidate` false: the
// presets come from every other one of the candidate strengths (7 of 14), in half the
// time.
struct CdefSource {
  std::array<const uint8_t*, 3> planes{};
  std::array<int, 3> strides{};
  int width = 0, height = 0;  // visible luma size
};
CdefParams choose_cdef(const std::array<PlaneView, 3>& planes, const CdefSource& source, int qindex,
                       std::span<const uint8_t> skip, double lambda, bool every_candidate = true);

}  // namespace svc::codec
