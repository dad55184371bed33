// SPDX-License-Identifier: BSD-2-Clause
// Quarter-pel motion-compensated prediction of blocks from a reference face, as in HEVC:
// a separable 8-tap luma filter at quarter-pel phases and a 4-tap chroma filter at
// eighth-pel phases (the luma vector read in eighth chroma pels), first to 14-bit
// intermediate samples, then rounded to 8 bits, or averaged at that precision for a
// bidirectional prediction. Sample coordinates outside the reference plane are clamped
// to it (edge extension), in one place (fetch_window in motion_compensation.cc), so any
// vector within max_vector_component() is valid even when it points wholly outside the
// face. Exact arithmetic is part of the bitstream contract (docs/codec.md, section 5.6).
//
// All functions are pure and thread-safe. Pointers and sizes are the caller's
// responsibility (planes of plane_width x plane_height samples, tightly packed).
#pragma once

#include <array>
#include <cstdint>

#include "codec/common/motion.h"
#include "svc/types.h"

namespace svc::codec {

// Largest |component| (quarter-pel units) of a luma vector for a face of this size:
// min(4 * max(width, height) + 128, 32767). Encoders clamp to it; decoders reject beyond.
int max_vector_component(int width, int height);
bool vector_in_range(MotionVector vector, int width, int height);

// Which filter a plane uses: luma positions in 1/4 pel with the 8-tap filter, chroma
// positions in 1/8 pel with the 4-tap filter.
enum class PlaneKind : uint8_t { kLuma, kChroma };

// The filter bank of a B-face (header byte 2, docs/codec.md 5.6): HEVC's DCT-based
// filters, AV1's EIGHTTAP_SMOOTH, or bilinear. References carry quantization noise and
// are often seen at another scale, where a smoother filter predicts better.
enum class InterpolationFilter : uint8_t { kRegular = 0, kSmooth = 1, kBilinear = 2 };
inline constexpr int kInterpolationFilterCount = 3;

// The filter taps of a phase (0..3 luma, 0..7 chroma) as 8 coefficients applied to the
// samples at offsets -3..4 from the integer position (chroma's 4 taps at -1..2, zeros
// elsewhere). Phase 0 is {0, 0, 0, 64, 0, 0, 0, 0} in every bank.
const std::array<int8_t, 8>& interpolation_taps(PlaneKind kind, int phase,
                                                InterpolationFilter filter = InterpolationFilter::kRegular);

// Prediction samples before rounding: 64 x the interpolated value (14 bits), stored
// less kIntermediateOffset so that they fit int16.
inline constexpr int kIntermediateOffset = 8192;
inline constexpr int kMaxPredictionBlock = 64;

// Predicts the block_width x block_height samples whose top-left sample is (x0, y0) in
// the current face, displaced by (vector_x, vector_y) in 1/4 (luma) or 1/8 (chroma)
// sample units, from `plane`, as intermediates into out (row stride out_stride). With
// X = 4 (x0 + i) + vector_x (8 for chroma), ix = X >> 2, fx = X & 3 (>> 3, & 7), likewise
// Y, iy, fy, h = taps(fx), v = taps(fy) and s(u, v) the plane sample clamped to it:
//   out = ((sum_j v[j] sum_i h[i] s(ix - 3 + i, iy - 3 + j)) >> 6) - 8192.
// Block widths 4..64 in steps of 4, heights 1..64.
void predict_block(const uint8_t* plane, int plane_width, int plane_height, PlaneKind kind, int x0, int y0,
                   int block_width, int block_height, int vector_x, int vector_y, int16_t* out, int out_stride,
                   InterpolationFilter filter = InterpolationFilter::kRegular);
// The samples predict_block's definition reads for that block, before clamping to the
// plane: columns x0..x1 and rows y0..y1 (inclusive), the 8-tap support (-3..4 around each
// sample's integer position) of every predicted sample, zero taps included, for every
// filter bank and plane kind (docs/codec.md 5.7, "Reference faces read").
struct ReadWindow {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};
ReadWindow prediction_window(PlaneKind kind, int x0, int y0, int block_width, int block_height, int vector_x,
                             int vector_y);
// The same definition evaluated sample by sample with explicit clamping: the plain
// reference predict_block is tested against (bit-identical output, any block size).
void predict_block_reference(const uint8_t* plane, int plane_width, int plane_height, PlaneKind kind, int x0,
                             int y0, int block_width, int block_height, int vector_x, int vector_y, int16_t* out,
                             int out_stride, InterpolationFilter filter = InterpolationFilter::kRegular);

// A 16x16 luma and two 8x8 chroma blocks, row-major, tightly packed: final samples, and
// intermediates of one reference's prediction.
struct MacroblockPrediction {
  std::array<uint8_t, 256> y;
  std::array<uint8_t, 64> cb;
  std::array<uint8_t, 64> cr;
};
struct MacroblockIntermediate {
  std::array<int16_t, 256> y;
  std::array<int16_t, 64> cb;
  std::array<int16_t, 64> cr;
};

// Predicts macroblock (mb_x, mb_y) of a face the size of `reference` from it: luma with
// `vector`, chroma with the same vector in 1/8 chroma pel.
void predict_macroblock(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector,
                        MacroblockIntermediate* out, InterpolationFilter filter = InterpolationFilter::kRegular);
// Luma only (for motion search): 256 intermediates into out.
void predict_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector, int16_t* out,
                             InterpolationFilter filter = InterpolationFilter::kRegular);

// Final samples of a single prediction: clip((in + 8192 + 32) >> 6, 0, 255).
void round_prediction(const int16_t* in, int count, uint8_t* out);
// Final samples of a bidirectional prediction: clip((a + b + 16384 + 64) >> 7, 0, 255).
void average_prediction(const int16_t* a, const int16_t* b, int count, uint8_t* out);
// Either of the above over a whole macroblock; `second` null for a single prediction.
void finish_prediction(const MacroblockIntermediate& first, const MacroblockIntermediate* second,
                       MacroblockPrediction* out);

}  // namespace svc::codec
