// SPDX-License-Identifier: BSD-2-Clause
// A B-face as both sides of the codec see it: its header, macroblock modes and
// partitions. Each 16x16 macroblock is intra-coded (as in intra frames, from its
// reconstructed neighbours), predicted from one of up to two reference faces (forward =
// reference 0, backward = reference 1) or from the average of both, or skipped
// (predicted with the neighbours' vectors, no residual). Each prediction is either a
// translation (one vector per macroblock and reference) or a warp (a vector per pixel,
// interpolated from node vectors at the macroblock corners: warp_prediction.h).
// Bitstream syntax: docs/codec.md, section 3.6. Decoding is
// codec/decoder/bframe_decoder.h, encoding codec/encoder/bframe_encoder.h.
#pragma once

#include <array>
#include <cstdint>

#include "codec/common/epipolar.h"
#include "codec/common/intra_frame.h"
#include "codec/common/motion.h"
#include "codec/common/motion_compensation.h"

namespace svc::codec {

// The B-face syntax the encoder writes, and the first a decoder reads: format 1.0's
// (docs/codec.md 1.1).
inline constexpr uint8_t kBFrameSyntaxVersion = 24;
inline constexpr uint8_t kBFrameSyntaxFirst = 24;
// Flags byte bit 4: coded inter macroblocks code whether their luma residual is one
// 16x16 transform block instead of four 8x8 ones, and each coded luma 8x8 block whether
// it is four 4x4 blocks (docs/codec.md 3.7).
inline constexpr uint8_t kInterTransformSizesFlag = 16;
// Byte 3 bit 2: each reference's epipolar lines open the range-coded data and vector
// differences are coded along and across them (docs/codec.md 3.8).
inline constexpr uint8_t kEpipolarLinesFlag = 4;
// Frame type and syntax version (byte 0, intra_codec.h), qindex, the references' byte
// (border units, interpolation filter, reference count, warp mask), flags (docs/codec.md 3.6).
inline constexpr int kBFrameReferencesByte = 2;
inline constexpr int kBFrameFlagsByte = 3;
inline constexpr int kBFrameHeaderBytes = 4;

// The border units (codec/cube_padding.h) of references `extra` samples wider and taller
// than the face (a border of extra / 2 on each side), or -1 when `extra` is not a valid
// border: 0 or an even multiple of 16 up to 2 x 16 x kMaxCubeBorderUnits.
int reference_border_units(int extra);

// The coding of one macroblock, as the decoder reports it (svc inspect draws intra red,
// forward/backward/bidirectional green, skipped blue).
enum class MacroblockMode : uint8_t {
  kIntra = 0,
  kForward = 1,        // predicted from reference 0
  kBackward = 2,       // predicted from reference 1
  kBidirectional = 3,  // rounded mean of both predictions
  kSkipped = 4,        // predicted mode and vectors inherited, no residual
};

// How an inter macroblock is split for prediction: each partition has its own mode
// (forward, backward or bidirectional) and vectors; the residual stays in 8x8 blocks.
enum class Partition : uint8_t {
  k16x16 = 0,
  k16x8 = 1,  // two 16x8 halves, top then bottom
  k8x16 = 2,  // two 8x16 halves, left then right
  k8x8 = 3,   // four 8x8 quarters in raster order
};

struct BFrameHeader {
  int qindex = 0;
  // Cube-map border of the references in units of 16 luma samples a side (0: the
  // references are the bare faces; codec/cube_padding.h builds padded ones).
  int border_units = 0;
  int loop_filters = 0;                // kLoopFilter* bits (intra_codec.h)
  bool transform_types = false;        // byte 3 kTransformTypesFlag: intra blocks code their type
  bool inter_transform_sizes = false;  // byte 3 kInterTransformSizesFlag
  bool epipolar_lines = false;         // byte 3 kEpipolarLinesFlag
  int reference_count = 0;             // 1 or 2
  int warp_mask = 0;                   // bit r: reference r may be warped
  InterpolationFilter filter = InterpolationFilter::kRegular;
};

}  // namespace svc::codec
