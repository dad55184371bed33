// SPDX-License-Identifier: BSD-2-Clause
// Decoding of a B-face (codec/common/bframe.h).
//
// Threading: reentrant (no shared state but each thread's scratch buffers, reused from
// frame to frame); decode different faces on different threads. Errors: kInvalidArgument
// for a bad size or reference set and kCorruptData for bytes that are not a valid
// B-face. It never reads outside its inputs, whatever the bytes.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/common/bframe.h"
#include "codec/common/cube_padding.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc::codec {

// Validates and reads the header of a B-face payload (kCorruptData / kUnsupported).
Status parse_b_frame_header(std::span<const uint8_t> bytes, BFrameHeader* out);

// The cube-border edges (FaceEdge bits of codec/common/cube_padding.h) of each padded
// reference that a B-face's predictions may read, and those they read (docs/codec.md 5.7,
// "Reference faces read"). The border samples across the other edges may hold anything:
// a payload whose prediction reads one is refused (kCorruptData), so the pixels decoded
// never depend on them.
struct BorderEdges {
  std::array<uint8_t, 2> allowed = {kAllFaceEdges, kAllFaceEdges};
  std::array<uint8_t, 2> read{};
};

// Decodes a B-face of width x height. ref1 must be null exactly when the frame was coded
// with one reference; references must be width x height with consistent planes, or
// padded by the border the header names (parse_b_frame_header; kInvalidArgument
// otherwise). `modes` (optional) receives the per-macroblock modes (a partitioned
// macroblock reports its last partition's), `partitions` (optional) the partitions
// (16x16 for intra and skipped macroblocks), `warped` (optional) 1 for each coded inter
// macroblock predicted by warping (5.6), else 0, all row-major. `border_edges`
// (optional; null allows every edge) limits the border the predictions may read and
// receives what they read. On error `out`, `modes`, `partitions`, `warped` and
// border_edges->read are left in an unspecified but valid state.
Status decode_b_frame(std::span<const uint8_t> bytes, int width, int height, const ImageYCbCr420& ref0,
                      const ImageYCbCr420* ref1, ImageYCbCr420* out, std::vector<MacroblockMode>* modes = nullptr,
                      std::vector<Partition>* partitions = nullptr, std::vector<uint8_t>* warped = nullptr,
                      BorderEdges* border_edges = nullptr);

}  // namespace svc::codec
