// Half-pel motion-compensated prediction of macroblocks from a reference face, as in
// MPEG-2: bilinear half-pel interpolation with rounding, chroma vectors derived from the
// luma vector, and the rounded mean of two predictions for bidirectional blocks. Sample
// coordinates outside the reference plane are clamped to it (edge extension), so any
// vector within max_vector_component() is valid even when it points wholly outside the
// face. Exact arithmetic is part of the bitstream contract (docs/codec.md, section 10).
//
// All functions are pure and thread-safe. Pointers and sizes are the caller's
// responsibility (planes of plane_width x plane_height samples, tightly packed).
#pragma once

#include <array>
#include <cstdint>

#include "codec/motion.h"
#include "svc/types.h"

namespace svc::codec {

// Largest |component| (half-pel units) of a luma vector for a face of this size:
// min(2 * max(width, height) + 64, 32767). Encoders clamp to it; decoders reject beyond.
int max_vector_component(int width, int height);
bool vector_in_range(MotionVector vector, int width, int height);

// The chroma vector of a 4:2:0 macroblock, in chroma half-pel units: each luma half-pel
// component divided by 2, truncated toward zero (MPEG-2).
inline MotionVector chroma_vector(MotionVector luma) {
  return MotionVector{static_cast<int16_t>(luma.x / 2), static_cast<int16_t>(luma.y / 2)};
}

// Predicts the block_width x block_height samples whose top-left sample is (x0, y0) in
// the current face, displaced by (vector_x, vector_y) half-pels, from `plane`. With
// X = 2 (x0 + i) + vector_x, ix = X >> 1, fx = X & 1 (likewise Y, iy, fy) and
// s(u, v) = plane[clip(v, 0, h-1)][clip(u, 0, w-1)]:
//   fx = fy = 0: s(ix, iy)
//   fx = 1, fy = 0: (s(ix, iy) + s(ix+1, iy) + 1) >> 1        (and the transpose)
//   fx = fy = 1: (s(ix, iy) + s(ix+1, iy) + s(ix, iy+1) + s(ix+1, iy+1) + 2) >> 2
// Block sizes up to kMaxPredictionBlock on each side.
inline constexpr int kMaxPredictionBlock = 64;
void predict_block(const uint8_t* plane, int plane_width, int plane_height, int x0, int y0, int block_width,
                   int block_height, int vector_x, int vector_y, uint8_t* out, int out_stride);
// The same definition evaluated sample by sample with explicit clamping: the plain
// reference predict_block is tested against (bit-identical output, any block size).
void predict_block_reference(const uint8_t* plane, int plane_width, int plane_height, int x0, int y0,
                             int block_width, int block_height, int vector_x, int vector_y, uint8_t* out,
                             int out_stride);

// A 16x16 luma and two 8x8 chroma prediction blocks, row-major, tightly packed.
struct MacroblockPrediction {
  std::array<uint8_t, 256> y;
  std::array<uint8_t, 64> cb;
  std::array<uint8_t, 64> cr;
};

// Predicts macroblock (mb_x, mb_y) of a face the size of `reference` from it.
void predict_macroblock(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector,
                        MacroblockPrediction* out);
// Luma only (for motion search): 256 samples into out.
void predict_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector, uint8_t* out);

// Bidirectional prediction: (a + b + 1) >> 1 per sample. `out` may alias a or b.
void average_predictions(const MacroblockPrediction& a, const MacroblockPrediction& b, MacroblockPrediction* out);
void average_samples(const uint8_t* a, const uint8_t* b, int count, uint8_t* out);

// Sum of absolute differences between a 16x16 block at `source` (row stride
// source_stride) and 256 packed prediction samples.
int sad_16x16(const uint8_t* source, int source_stride, const uint8_t* prediction);
// The plain per-sample loop sad_16x16 is tested against.
int sad_16x16_reference(const uint8_t* source, int source_stride, const uint8_t* prediction);

// SAD between the 16x16 luma block at `source` (row stride source_stride) and the
// prediction of macroblock (mb_x, mb_y) from `reference` with `vector`, stopping early:
// returns the exact SAD when it is <= limit, otherwise some value > limit. Equals
// sad_16x16 over predict_macroblock_luma (tested); faster for motion search.
int sad_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, MotionVector vector,
                        const uint8_t* source, int source_stride, int limit);

}  // namespace svc::codec
