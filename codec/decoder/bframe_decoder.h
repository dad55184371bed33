// SPDX-License-Identifier: BSD-2-Clause
// Decoding of a B-face (codec/common/bframe.h).
//
// Threading: reentrant (no shared state but each thread's scratch buffers, reused from
// frame to frame); decode different faces on different threads. Errors: kInvalidArgument
// for a bad size or reference set and kCorruptData for bytes that are not a valid
// B-face. It never reads outside its inputs, whatever the bytes.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/common/bframe.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc::codec {

// Validates and reads the header of a B-face payload (kCorruptData / kUnsupported).
Status parse_b_frame_header(std::span<const uint8_t> bytes, BFrameHeader* out);

// Decodes a B-face of width x height. ref1 must be null exactly when the frame was coded
// with one reference; references must be width x height with consistent planes, or
// padded by the border the header names (parse_b_frame_header; kInvalidArgument
// otherwise). `modes` (optional) receives the per-macroblock modes (a partitioned
// macroblock reports its last partition's), `partitions` (optional) the partitions
// (16x16 for intra and skipped macroblocks), `warped` (optional) 1 for each coded inter
// macroblock predicted by warping (5.6), else 0, all row-major. On error `out`, `modes`,
// `partitions` and `warped` are left in an unspecified but valid state.
Status decode_b_frame(std::span<const uint8_t> bytes, int width, int height, const ImageYCbCr420& ref0,
                      const ImageYCbCr420* ref1, ImageYCbCr420* out, std::vector<MacroblockMode>* modes = nullptr,
                      std::vector<Partition>* partitions = nullptr, std::vector<uint8_t>* warped = nullptr);

}  // namespace svc::codec
