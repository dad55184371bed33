// SPDX-License-Identifier: BSD-2-Clause
// The YCbCr 4:2:0 -> RGB conversion of decoded faces; the encoder's RGB -> YCbCr is
// codec/encoder/rgb_to_ycbcr.h. Full-range BT.601 (as JFIF), 16-bit fixed point; exact
// definition in docs/codec.md. All functions are pure and thread-safe; sizes are the
// caller's responsibility.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "svc/types.h"

namespace svc::codec {

// rgb_out: width*height*3 bytes. Chroma is upsampled by replication (nearest).
void ycbcr420_to_rgb(const ImageYCbCr420& image, uint8_t* rgb_out);

// Writes `image` into the caller's planes in `format` and row `order`, straight from the
// planes (no intermediate image). planes and strides as PixelBuffer's, already checked
// to hold the image (pixel_row_bytes, pixel_plane_rows).
void ycbcr420_to_pixels(const ImageYCbCr420& image, PixelFormat format, RowOrder order,
                        const std::array<uint8_t*, 3>& planes, const std::array<size_t, 3>& strides);

// The per-pixel form of the same formulas, for tools and tests.
void ycbcr_to_rgb_pixel(uint8_t y, uint8_t cb, uint8_t cr, uint8_t rgb_out[3]);

// Plain per-pixel reference implementation (used by tests to check the optimized loop
// above; same results bit for bit).
void ycbcr420_to_rgb_reference(const ImageYCbCr420& image, uint8_t* rgb_out);

}  // namespace svc::codec
