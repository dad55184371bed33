// SPDX-License-Identifier: BSD-2-Clause
// Copying a frame's working planes (padded to whole blocks, each with its own row
// stride) into the tightly packed 4:2:0 image the codec hands out.
// Threading: pure function. Sizes and strides are the caller's responsibility.
#pragma once

#include <array>
#include <cstdint>

#include "svc/types.h"

namespace svc::codec {

// Fills `out` with the top-left width x height luma samples of planes[0] and the
// ((width + 1) / 2) x ((height + 1) / 2) chroma samples of planes[1] and planes[2],
// each plane read with its stride. Keeps the capacity `out` already has and never
// zeroes what it is about to overwrite.
void copy_planes_to_image(const std::array<const uint8_t*, 3>& planes, const std::array<int, 3>& strides, int width,
                          int height, ImageYCbCr420* out);

}  // namespace svc::codec
