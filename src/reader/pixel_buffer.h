// SPDX-License-Identifier: BSD-2-Clause
// Checks a caller's PixelBuffer against the face it is to receive.
#pragma once

#include "svc/status.h"
#include "svc/types.h"

namespace svc::reader_internal {

// kInvalidArgument, naming the plane and the bytes it needs, unless `buffer` is a known
// format and row order whose planes and strides hold a width x height face.
Status check_pixel_buffer(const PixelBuffer& buffer, int width, int height);

// Writes `image` into the checked `buffer`.
void write_pixels(const ImageYCbCr420& image, const PixelBuffer& buffer);

}  // namespace svc::reader_internal
