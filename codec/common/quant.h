// SPDX-License-Identifier: BSD-2-Clause
// Quantization of 8x8 DCT blocks with MPEG-2's weighting matrices and a logarithmic
// quantizer index (qindex 0..255, the step doubling every 32 indices), shared by intra frames and the residual
// blocks of B-faces. Dequantization is exact integer arithmetic and part of the
// bitstream contract (docs/codec.md); quantization runs only in the encoder and may use
// float with rate-distortion rounding offsets (codec/encoder/quantize.h). Quantizer
// objects are immutable after make_residual_quantizer() and may be shared between threads.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>

#include "codec/common/dct.h"
#include "codec/common/transform_size.h"
#include "codec/common/transform_type.h"

namespace svc::codec {

// MPEG-2's default intra matrix in natural (row-major) order: the weights of
// ResidualMatrix::kWeighted (residual_weight).
extern const std::array<uint8_t, 64> kDefaultIntraMatrix;

// Largest |level| the quantizer produces and the bitstream allows.
inline constexpr int kMaxLevel = 4095;

inline constexpr int kMinQIndex = 0;
inline constexpr int kMaxQIndex = 255;
// Indices per doubling of the step.
inline constexpr int kQIndexPerOctave = 32;
// Dequantization multipliers are in units of 1 / 2^kStepBits of a coefficient.
inline constexpr int kStepBits = 8;

// The quantizer scale of an index in 1/256 units: T[qindex % 32] << (qindex / 32) with
// T[k] = round(128 * 2^(k / 32)); 128 (an MPEG-2 quantizer_scale of 0.5) at index 0,
// 512 (scale 2) at 64, 32128 (125.5) at 255. Part of the bitstream contract.
int quantizer_scale_q8(int qindex);

// The flat residual step of a transform size for `qindex` (clamped to 0..255), in 1/256
// coefficient units: step = (16 * scale + 8) >> 4 (MPEG-2's flat non-intra weight 16,
// so the scale itself) for 4x4 and 8x8 (orthonormal coefficients); max((step + 1) >> 1,
// 128) for 16x16, whose coefficients are half the orthonormal ones. Every transform size
// derives its steps from this one. Part of the bitstream contract.
int residual_step(TransformSize size, int qindex);

// Quantization matrices of intra-frame residual blocks (docs/codec.md 5.4, "Weighted
// matrices"): flat (one step per size, the default: it measures better in PSNR) or
// weighted by frequency, coarser towards the high frequencies the eye sees least.
enum class ResidualMatrix : uint8_t { kFlat = 0, kWeighted = 1 };

// The weight, in 1/16, of natural position `position` of a residual block of `size`
// under kWeighted: MPEG-2's intra matrix with its DC entry 16, sampled at the
// frequency the position stands for (16x16: entry (r/2, c/2); 4x4: entry (2r, 2c)).
int residual_weight(TransformSize size, int position);

// The step at `position` of a residual block: residual_step under kFlat, else
// max((residual_step * residual_weight + 8) >> 4, 128). Part of the bitstream contract.
int residual_step(TransformSize size, int qindex, ResidualMatrix matrix, int position);

struct Quantizer {
  int qindex = 0;
  TransformSize size = TransformSize::k8x8;  // blocks of transform_area(size) values
  // coefficient = sign(level) * ((|level| * scale[i] + 128) >> 8), i in natural order;
  // scale[i] = residual_step(size, qindex, matrix, i).
  std::array<int32_t, kMaxTransformArea> scale{};
  // Encoder only: 256 / scale[i] and the rounding offsets (fractions of a step added
  // before truncation; 0.5 is plain rounding, smaller values widen the dead zone).
  std::array<float, kMaxTransformArea> inverse_step{};
  float rounding_dc = 0.5f;
  float rounding_ac = 0.5f;
};

// The quantizer of residual blocks of any size (flat unless `matrix` says); qindex is
// clamped to [kMinQIndex, kMaxQIndex]. Rounding offsets 0.2: a wide dead zone, most
// residual blocks become empty.
Quantizer make_residual_quantizer(TransformSize size, int qindex, ResidualMatrix matrix = ResidualMatrix::kFlat);

// Exact integer dequantization of one level at natural position `index`, saturated to
// [kMinCoefficient, kMaxCoefficient]. Inline: the encoder's rate-distortion loops call
// it per coefficient and trial.
inline int dequantize_level(const Quantizer& quantizer, int index, int level) {
  const int magnitude =
      (std::min(std::abs(level), kMaxLevel + 1) * quantizer.scale[index] + (1 << (kStepBits - 1))) >> kStepBits;
  return level < 0 ? std::max(-magnitude, kMinCoefficient) : std::min(magnitude, kMaxCoefficient);
}
void dequantize_block(const Quantizer& quantizer, const int16_t* levels, int16_t* coefficients);

// Dequantization + integer inverse DCT: what the decoder reconstructs, before the caller
// adds the prediction and clips to [0, 255].
void dequantize_inverse_transform_block(const Quantizer& quantizer, const int16_t* levels, int16_t* samples);

}  // namespace svc::codec
