// Warped (mesh) motion compensation: a macroblock predicted with a smoothly varying
// vector per pixel instead of one translation. Each macroblock corner is a node carrying
// a vector in 1/8 pel; a pixel's vector is the bilinear interpolation of its macroblock's
// four corner nodes at the pixel centre, rounded to 1/16 pel, and the reference is sampled
// there with bilinear interpolation (edge-clamped). Chroma uses the same node field at
// half resolution. This follows perspective change (floors, walls and ceilings seen
// obliquely) that a single vector per 16x16 block cannot. Exact integer arithmetic is part
// of the bitstream contract (docs/codec.md, section 10.1).
//
// All functions are pure and thread-safe; pointers and sizes are the caller's
// responsibility as in motion_compensation.h.
#pragma once

#include <array>
#include <cstdint>

#include "codec/motion.h"
#include "codec/motion_compensation.h"
#include "svc/types.h"

namespace svc::codec {

// Corner nodes of one macroblock in the order top-left, top-right, bottom-left,
// bottom-right, in 1/8 luma pel.
using WarpCorners = std::array<WarpNode, 4>;

// Largest |component| (1/8 pel) of a node vector for a face of this size:
// 4 * max_vector_component(width, height). Encoders clamp to it; decoders reject beyond.
int max_warp_node_component(int width, int height);

// Predicts the 16x16 luma block of macroblock (mb_x, mb_y) and its two 8x8 chroma blocks
// from `reference` (same size as the current face). For luma sample (u, v) of the block,
// with a = 2u + 1, b = 2v + 1 (pixel centres in half-pixels from the corner) and
//   S = (32-a)(32-b) N0 + a(32-b) N1 + (32-a) b N2 + a b N3     (per component)
//   V = (S + 256) >> 9                                          (1/16 pel)
//   X = 16 (16 mb_x + u) + Vx, Y likewise; ix = X >> 4, fx = X & 15 (iy, fy likewise)
//   p = ((16-fx)(16-fy) s(ix,iy) + fx(16-fy) s(ix+1,iy) + (16-fx) fy s(ix,iy+1)
//        + fx fy s(ix+1,iy+1) + 128) >> 8,   s clamped to the plane.
// Chroma sample (u, v) of the 8x8 block: a = 2u + 1, b = 2v + 1 over 16,
//   S = (16-a)(16-b) N0 + a(16-b) N1 + (16-a) b N2 + a b N3, V = (S + 128) >> 8 in 1/16
// chroma pel (a luma 1/8 pel is a chroma 1/16 pel), X = 16 (8 mb_x + u) + Vx.
void predict_warp_macroblock(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                             MacroblockPrediction* out);
// Luma only (256 samples, row-major), for screening.
void predict_warp_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                                  uint8_t* out);
// Chroma only (out->cb and out->cr; out->y untouched), completing a luma-only prediction.
void predict_warp_macroblock_chroma(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                                    MacroblockPrediction* out);

// The same definition evaluated sample by sample in 64-bit arithmetic with explicit
// clamping: the plain reference the fast path is tested against (bit-identical output).
void predict_warp_macroblock_reference(const ImageYCbCr420& reference, int mb_x, int mb_y,
                                       const WarpCorners& corners, MacroblockPrediction* out);

}  // namespace svc::codec
