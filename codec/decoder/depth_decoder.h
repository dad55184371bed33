// SPDX-License-Identifier: BSD-2-Clause
// Decoding a face's depth plane (docs/codec.md section 8).
// Threading: a plain function; calls on different planes may run at once.
#pragma once

#include <cstdint>
#include <span>

#include "codec/common/depth.h"
#include "svc/status.h"

namespace svc::codec {

// Whether a depth payload is predicted from reference cubes (its decode then needs
// them); false for a payload too short to say.
bool depth_payload_is_inter(std::span<const uint8_t> payload);

// Decodes a width x height depth plane into `codes` (width * height, row 0 at the top;
// 0 where the face has no geometry). An inter payload needs `references` (the faces
// docs/codec.md 8.3 lists, in its order) and the face's camera `target`; an intra one
// ignores them. kCorruptData for a payload that is truncated, has an unknown version or
// flags, or needs references it was not given; the codes are unspecified then.
Status decode_depth(std::span<const uint8_t> payload, int width, int height,
                    std::span<const DepthReference> references, const Camera& target, uint16_t* codes);

}  // namespace svc::codec
