// SPDX-License-Identifier: BSD-2-Clause
// The encoder's pixel kernels behind a table of their own, built like the shared one
// (codec/common/dsp/dsp.h): every kernel has a plain C++ reference, always compiled, and
// optional x86 or AArch64 NEON variants that must match it bit for bit, chosen once by
// the same CPU flags (active_cpu_flags(), so SVC_CPU_MASK applies here too). Forward
// transforms, quantization and the block distances of the searches serve the encoder
// alone, so they live outside the decoder library. The encoder calls them only through
// get_encoder_dsp(); tests and the kernel checker build tables for chosen feature sets
// with make_encoder_dsp_table(). docs/kernels.md describes how to add a kernel.
#pragma once

#include <cstddef>
#include <cstdint>

#include "codec/common/dsp/dsp.h"

namespace svc::codec::dsp {

struct EncoderDspTable {
  // 8x8, 4x4 and 16x16 float forward DCTs (docs/codec.md 5.5; 4x4 and 8x8 orthonormal,
  // 16x16 half the orthonormal scale): the transposes of the shared table's integer
  // inverses; blocks row-major.
  void (*forward_dct_8x8)(const float* samples, float* coefficients);
  void (*forward_dct_4x4)(const float* samples, float* coefficients);
  void (*forward_dct_16x16)(const float* samples, float* coefficients);
  // The float forward transforms of the intra transform types (docs/codec.md 5.5.2),
  // `type` 1..3 for squares (bit 0: rows use the DST-VII, bit 1: columns; the other
  // direction takes HEVC's integer DCT of the size, at 8x8 too), at the scale of the
  // size's DCT; and of the rectangular blocks (7.3; W x H, W samples a row), `type`
  // 0..3, 0 being DCT_DCT, coefficients at 1/sqrt(2) of the orthonormal scale (16x8,
  // 8x16), orthonormal (16x4, 4x16) or at sqrt(2) of it (8x4, 4x8).
  void (*forward_typed_4x4)(int type, const float* samples, float* coefficients);
  void (*forward_typed_8x8)(int type, const float* samples, float* coefficients);
  void (*forward_typed_16x16)(int type, const float* samples, float* coefficients);
  void (*forward_typed_16x8)(int type, const float* samples, float* coefficients);
  void (*forward_typed_8x16)(int type, const float* samples, float* coefficients);
  void (*forward_typed_16x4)(int type, const float* samples, float* coefficients);
  void (*forward_typed_4x16)(int type, const float* samples, float* coefficients);
  void (*forward_typed_8x4)(int type, const float* samples, float* coefficients);
  void (*forward_typed_4x8)(int type, const float* samples, float* coefficients);

  // Quantizes 64 coefficients: level = trunc(|c| inverse_step[i] + rounding) capped at
  // 4095, sign of c; rounding is rounding_dc at i = 0. Returns the non-zero count.
  int (*quantize_8x8)(const float* coefficients, const float* inverse_step, float rounding_dc, float rounding_ac,
                      int16_t* levels);

  // SAD of a 16x16 block against 256 packed samples (motion search and mode decision).
  int (*sad_16x16)(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction);
  // SAD of a width x height block (width 8 or 16, height 1 to 16) against the rounded-up
  // average (a + b + 1) >> 1 of two reference blocks sharing one stride (b may equal a)
  // (motion search on half-pel planes).
  int (*sad_average)(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* a, const uint8_t* b,
                     ptrdiff_t reference_stride, int width, int height);
  // Sum of absolute 8x8 (4x4) Hadamard coefficients (unnormalised) of source - prediction
  // (first-stage estimates: intra modes and partitions).
  int (*satd_8x8)(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction);
  int (*satd_4x4)(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction);
  // The sum of the four 8x8 quadrants' SATDs of a 16x16 block, `prediction` packed 16
  // samples a row (first-stage estimates of whole macroblocks).
  int (*satd_16x16)(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction);
};

// The table for this machine (active_cpu_flags()), built once on first use; thread-safe.
const EncoderDspTable& build_process_encoder_dsp_table();
inline const EncoderDspTable& get_encoder_dsp() {
  static const EncoderDspTable& table = build_process_encoder_dsp_table();
  return table;
}
// A table using only variants whose features are in `cpu_flags` (0: plain references).
EncoderDspTable make_encoder_dsp_table(unsigned cpu_flags);

}  // namespace svc::codec::dsp
