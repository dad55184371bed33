// SPDX-License-Identifier: BSD-2-Clause
// The encoder's sums of absolute differences against 16x16 predictions (motion search
// and mode decision), through its kernel table (codec/encoder/dsp/encoder_dsp.h). Pure
// and thread-safe.
#pragma once

#include <cstdint>

#include "codec/common/motion_compensation.h"

namespace svc::codec {

// Sum of absolute differences between a 16x16 block at `source` (row stride
// source_stride) and 256 packed prediction samples.
int sad_16x16(const uint8_t* source, int source_stride, const uint8_t* prediction);
// The plain per-sample loop sad_16x16 is tested against.
int sad_16x16_reference(const uint8_t* source, int source_stride, const uint8_t* prediction);

// SAD between the 16x16 luma block at `source` (row stride source_stride) and the
// single prediction of macroblock (mb_x, mb_y) from `reference` with `vector`.
int sad_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector,
                        const uint8_t* source, int source_stride,
                        InterpolationFilter filter = InterpolationFilter::kRegular);

}  // namespace svc::codec
