// The one RGB <-> YCbCr 4:2:0 conversion used by both encoder and decoder.
// Full-range BT.601 (as JFIF), 16-bit fixed point; exact definition in docs/codec.md.
// All functions are pure and thread-safe; sizes are the caller's responsibility.
#pragma once

#include <cstdint>

#include "svc/types.h"

namespace svc::codec {

// rgb: width*height*3 bytes, row 0 at the top. Chroma is the rounded mean of each 2x2
// block (edge pixels replicated for odd sizes).
ImageYCbCr420 rgb_to_ycbcr420(const uint8_t* rgb, int width, int height);

// rgb_out: width*height*3 bytes. Chroma is upsampled by replication (nearest).
void ycbcr420_to_rgb(const ImageYCbCr420& image, uint8_t* rgb_out);

// Per-pixel forms of the same formulas (no subsampling), for tools and tests.
struct YCbCr {
  uint8_t y, cb, cr;
};
YCbCr rgb_to_ycbcr_pixel(uint8_t r, uint8_t g, uint8_t b);
void ycbcr_to_rgb_pixel(uint8_t y, uint8_t cb, uint8_t cr, uint8_t rgb_out[3]);

// Plain per-pixel reference implementations of the two image conversions (used by tests
// to check the optimized loops above; same results bit for bit).
ImageYCbCr420 rgb_to_ycbcr420_reference(const uint8_t* rgb, int width, int height);
void ycbcr420_to_rgb_reference(const ImageYCbCr420& image, uint8_t* rgb_out);

}  // namespace svc::codec
