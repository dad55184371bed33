// SPDX-License-Identifier: BSD-2-Clause
// Intra frame decoding (docs/codec.md): the parse stage into a CoefficientFrame, and
// parse plus reconstruction. Pure computation: no files.
#pragma once

#include <cstdint>
#include <span>

#include "codec/common/intra_frame.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc::codec {

// Entropy-decodes and dequantizes an intra frame of the given size. Errors:
// kInvalidArgument for a size outside [1, kMaxFrameDimension]; kCorruptData for a bad
// header, invalid syntax, truncated payload or trailing bytes (message names the byte
// offset or block). Never reads outside `bytes`.
// `decoded` (optional) receives the levels unpacked as well; on error it is unspecified.
Status parse_intra_frame(std::span<const uint8_t> bytes, int width, int height, CoefficientFrame* out,
                         DecodedLevels* decoded = nullptr);

// parse_intra_frame followed by reconstruct_intra_frame.
Status decode_intra_frame(std::span<const uint8_t> bytes, int width, int height, ImageYCbCr420* out);

}  // namespace svc::codec
