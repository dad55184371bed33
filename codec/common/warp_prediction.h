// SPDX-License-Identifier: BSD-2-Clause
// Warped (mesh) motion compensation: a macroblock predicted with a smoothly varying
// vector instead of one translation. Each macroblock corner is a node carrying a vector
// in 1/8 pel; every 4x4 luma block (and every 4x4 chroma block, an 8x8 luma area) takes
// the bilinear interpolation of its macroblock's four corner nodes at its centre,
// rounded to 1/4 luma pel (1/8 chroma pel), and is predicted through the same
// interpolation filters as a translation (motion_compensation.h), as VVC's affine and
// AV1's warped motion predict per sub-block. This follows perspective change (floors,
// walls and ceilings seen obliquely) that a single vector per 16x16 block cannot. Exact
// integer arithmetic is part of the bitstream contract (docs/codec.md, section 5.6).
//
// All functions are pure and thread-safe; pointers and sizes are the caller's
// responsibility as in motion_compensation.h.
#pragma once

#include <array>
#include <cstdint>

#include "codec/common/motion.h"
#include "codec/common/motion_compensation.h"
#include "svc/types.h"

namespace svc::codec {

// Corner nodes of one macroblock in the order top-left, top-right, bottom-left,
// bottom-right, in 1/8 luma pel.
using WarpCorners = std::array<WarpNode, 4>;

// Largest |component| (1/8 pel) of a node vector for a face of this size:
// 2 * max_vector_component(width, height). Encoders clamp to it; decoders reject beyond.
int max_warp_node_component(int width, int height);

// The vector of the sub-block centred at (a, b) half luma pixels from the macroblock's
// top-left corner (0 < a, b < 32), in 1/4 luma pel:
//   S = (32-a)(32-b) N0 + a(32-b) N1 + (32-a) b N2 + a b N3,  V = (S + 1024) >> 11.
// Luma block (p, q) (0..3) is centred at a = 8p + 4, b = 8q + 4; chroma block (p, q)
// (0..1) at a = 16p + 8, b = 16q + 8, and reads V in 1/8 chroma pel.
std::array<int, 2> warp_subblock_vector(const WarpCorners& corners, int a, int b);

// Intermediates of the warped prediction of macroblock (mb_x, mb_y) from `reference`
// (same size as the current face): luma and chroma, luma only (for screening), or chroma
// only (completing a luma-only prediction; out->y untouched).
void predict_warp_macroblock(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                             MacroblockIntermediate* out,
                             InterpolationFilter filter = InterpolationFilter::kRegular);
void predict_warp_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                                  int16_t* out, InterpolationFilter filter = InterpolationFilter::kRegular);
void predict_warp_macroblock_chroma(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                                    MacroblockIntermediate* out,
                                    InterpolationFilter filter = InterpolationFilter::kRegular);

// The same definition with 64-bit vector arithmetic and predict_block_reference: the
// plain reference the fast path is tested against (bit-identical output).
void predict_warp_macroblock_reference(const ImageYCbCr420& reference, int mb_x, int mb_y,
                                       const WarpCorners& corners, MacroblockIntermediate* out,
                                       InterpolationFilter filter = InterpolationFilter::kRegular);

}  // namespace svc::codec
