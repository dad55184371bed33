// SPDX-License-Identifier: BSD-2-Clause
// Full-range BT.601 (JFIF) color conversion in 16-bit fixed point, per pixel: the
// definition the row kernels and codec/color.cc share. The constants sum exactly to
// 65536 (luma) and 0 (chroma), so greys map to Y = grey, Cb = Cr = 128 and back without
// error.
#pragma once

#include <algorithm>
#include <cstdint>

namespace svc::codec::dsp::color {

inline constexpr int kYR = 19595, kYG = 38470, kYB = 7471;        // 0.299, 0.587, 0.114
inline constexpr int kCbR = -11059, kCbG = -21709, kCbB = 32768;  // -0.168736, -0.331264, 0.5
inline constexpr int kCrR = 32768, kCrG = -27439, kCrB = -5329;   // 0.5, -0.418688, -0.081312
inline constexpr int kRCr = 91881;                                // 1.402
inline constexpr int kGCb = -22554, kGCr = -46802;                // -0.344136, -0.714136
inline constexpr int kBCb = 116130;                               // 1.772

inline uint8_t clamp_byte(int v) { return static_cast<uint8_t>(std::clamp(v, 0, 255)); }

inline uint8_t luma(int r, int g, int b) { return clamp_byte((kYR * r + kYG * g + kYB * b + 32768) >> 16); }
inline int cb_unscaled(int r, int g, int b) { return kCbR * r + kCbG * g + kCbB * b; }
inline int cr_unscaled(int r, int g, int b) { return kCrR * r + kCrG * g + kCrB * b; }

// Chroma of a 2x2 group from the sum of the four unscaled values: rounded mean + 128.
inline uint8_t chroma_from_sum4(int sum) { return clamp_byte((sum + (1 << 17) + (128 << 18)) >> 18); }

inline void to_rgb(int y, int cb, int cr, uint8_t* out) {
  const int dcb = cb - 128, dcr = cr - 128;
  out[0] = clamp_byte(y + ((kRCr * dcr + 32768) >> 16));
  out[1] = clamp_byte(y + ((kGCb * dcb + kGCr * dcr + 32768) >> 16));
  out[2] = clamp_byte(y + ((kBCb * dcb + 32768) >> 16));
}

}  // namespace svc::codec::dsp::color
