// SPDX-License-Identifier: BSD-2-Clause
// Checks a caller's PixelBuffer against the face it is to receive.
#pragma once

#include <cstdint>
#include <vector>

#include "svc/status.h"
#include "svc/types.h"

namespace svc::reader_internal {

// kInvalidArgument, naming the plane and the bytes it needs, unless `buffer` is a known
// format and row order whose planes and strides hold a width x height face.
Status check_pixel_buffer(const PixelBuffer& buffer, int width, int height);

// Writes `image` into the checked `buffer`.
void write_pixels(const ImageYCbCr420& image, const PixelBuffer& buffer);

// kInvalidArgument, naming what is wrong, unless `buffer` is a known format and row
// order whose stride and size hold a width x height depth plane.
Status check_depth_buffer(const DepthBuffer& buffer, int width, int height);

// Writes inverse-depth `codes` (width x height) of a face with near plane `near_plane`
// into the checked `buffer`.
void write_depth(const std::vector<uint16_t>& codes, int width, int height, double near_plane,
                 const DepthBuffer& buffer);

}  // namespace svc::reader_internal
