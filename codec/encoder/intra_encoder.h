// SPDX-License-Identifier: BSD-2-Clause
// Intra frame encoding: the coding tools an encode may use and the frame encoder.
// Pure computation: no files.
#pragma once

#include <cstdint>
#include <vector>

#include "codec/common/intra_frame.h"
#include "codec/common/quant.h"
#include "codec/encoder/syntax_account.h"
#include "svc/types.h"

namespace svc::codec {

// The 16x16 halves and strips partitions of a luma macroblock (two each way), and the
// 4x4, 8x4 and 4x8 partitions of an 8x8 block: what CodingParams::rectangular_trials and
// small_trials count.
inline constexpr int kRectangularPartitions = 4;
inline constexpr int kSmallPartitions = 3;

struct CodingParams {
  int qindex = 96;  // quantizer index, kMinQIndex..kMaxQIndex (codec/quant.h)
  // Encoder restriction: when false, every block uses the planar or DC mode only.
  bool directional_intra = true;
  // Encoder choice: when false, each block takes the mode of least SATD (plus a rate
  // term) and its levels as quantized, without the rate-distortion comparison of a
  // few modes and of dropping the levels.
  bool rd_intra_search = true;
  // Encoder choice: with every mode allowed, rank by SATD only planar, DC, the most
  // probable modes, every fourth angular mode and the two on each side of the best of
  // those (at most 18 modes instead of 35): for B-face intra macroblocks, where the
  // search runs on every macroblock (docs/encoder.md 5), and for intra frames at encoder
  // speeds from 1 on (6.2).
  bool coarse_mode_search = false;
  // Encoder restriction: when false, 8x8 luma blocks are never split into 4x4, 8x4 or
  // 4x8 blocks (the split flags are still coded).
  bool small_blocks = true;
  // Encoder choice, with transform sizes: how many of the four 16x16 halves and strips
  // partitions the rate-distortion search codes (the cheapest by an open-loop SATD
  // estimate; the 8x8 split and the 16x16 block always), and how many of the 4x4, 8x4
  // and 4x8 partitions each coded 8x8 block tries (likewise). The defaults: every one
  // (docs/encoder.md 2.2).
  int rectangular_trials = kRectangularPartitions;
  int small_trials = kSmallPartitions;
  // Offers the deblocking filter; the encoder switches it on for the frame where it lowers
  // the squared error against the source (the flag costs nothing else).
  bool deblocking = true;
  // Offers CDEF (cdef.h); the encoder chooses its presets and units by squared error
  // plus their bits, and leaves it off where it does not pay.
  bool cdef = true;
  // Encoder choice: CDEF presets from all 14 candidate strengths; off, from every other
  // one (choose_cdef's every_candidate).
  bool full_cdef_search = true;
  // Encoder choice: levels by rate-distortion optimized quantization (codec/rdoq.h)
  // rather than by rounding with a dead zone.
  bool rdoq = true;
  // Encoder restriction: when false, every luma macroblock is coded as four 8x8 blocks
  // (no 16x16 or 4x4 transform blocks; the partition flags are still coded).
  bool transform_sizes = true;
  // Encoder restriction: when false, no chroma block uses CfL (chroma from luma,
  // codec/cfl.h; the CfL flags are still coded).
  bool cfl = true;
  // Offers the intra transform types (DST-VII per direction, docs/codec.md 5.5.2),
  // signalled in the header (kTransformTypesFlag): the encoder picks each coded block's
  // type by rate-distortion cost. When false, every block is DCT_DCT and no type is coded.
  bool transform_types = true;
  // The residual quantization matrix (quant.h), signalled in the header (byte 2 bit 2).
  ResidualMatrix residual_matrix = ResidualMatrix::kFlat;
};

// Encodes an intra frame. `reconstruction` (optional) receives exactly what the
// decoder will produce. `source` must have positive size and planes of the sizes
// ImageYCbCr420 documents; otherwise the result is empty (which no decoder accepts).
// qindex is clamped to [kMinQIndex, kMaxQIndex]. `syntax` (optional) receives the
// frame's bits by syntax element (syntax_account.h; the header bytes count as header);
// the bytes do not depend on it. Thread-safe (no shared state).
std::vector<uint8_t> encode_intra_frame(const ImageYCbCr420& source, const CodingParams& params,
                                        ImageYCbCr420* reconstruction, SyntaxBits* syntax = nullptr);

}  // namespace svc::codec
