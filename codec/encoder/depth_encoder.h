// SPDX-License-Identifier: BSD-2-Clause
// Coding a face's depth plane (docs/codec.md section 8, docs/encoder.md "Depth").
// Threading: a plain function; calls on different planes may run at once.
#pragma once

#include <cstdint>
#include <vector>

#include "codec/common/depth.h"

namespace svc::codec {

// inverse_depth_code of every eye depth of a face with near plane `near_plane`.
std::vector<uint16_t> inverse_depth_codes(const std::vector<float>& eye_z, double near_plane);

struct DepthEncodeResult {
  std::vector<uint8_t> payload;
  std::vector<uint16_t> reconstructed;  // what the decoder gets, width * height
};

// Codes `codes` (width * height inverse-depth codes, 0 without geometry) so that every
// reconstructed code is within `max_error` (0..kMaxDepthError) of the source and every
// 0 stays 0. With a `prediction` (predict_depth of the reference cubes' reconstructed
// depth) the payload is an inter one; null codes it on its own.
DepthEncodeResult encode_depth(const std::vector<uint16_t>& codes, int width, int height, int max_error,
                               const DepthPrediction* prediction);

}  // namespace svc::codec
