// SPDX-License-Identifier: BSD-2-Clause
// The encoder's one lambda formula: squared error per estimated bit at a quantizer
// index, factor x scale^2, scale being the index's quantizer scale as the MPEG-2
// quantizer_scale it replaces (codec/common/quant.h). Each decision passes its own
// factor (docs/encoder.md lists them).
#pragma once

#include "codec/common/quant.h"

namespace svc::codec {

// The quantizer scale of an index, 1.0 at a quantizer_scale of 1.
inline double quantizer_scale(int qindex) { return quantizer_scale_q8(qindex) / 256.0; }

inline double rd_lambda(int qindex, double factor) {
  const double scale = quantizer_scale(qindex);
  return factor * scale * scale;
}

}  // namespace svc::codec
