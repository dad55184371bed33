// MPEG-2 style quantization of 8x8 DCT blocks, shared by intra frames and the residual
// blocks of B-frames. Dequantization is exact integer arithmetic and part of the
// bitstream contract (docs/codec.md); quantization runs only in the encoder and may use
// float with rate-distortion rounding offsets. Quantizer objects are immutable after
// make_quantizer() and may be shared between threads.
#pragma once

#include <array>
#include <cstdint>

namespace svc::codec {

enum class BlockKind : uint8_t {
  kIntra = 0,     // pixels, default intra matrix, DC with its own step
  kNonIntra = 1,  // prediction residuals, default non-intra matrix (flat 16)
};

// MPEG-2 default matrices in natural (row-major) order.
extern const std::array<uint8_t, 64> kDefaultIntraMatrix;
extern const std::array<uint8_t, 64> kDefaultNonIntraMatrix;

// Largest |level| the quantizer produces and the bitstream allows.
inline constexpr int kMaxLevel = 4095;

// The intra DC step for a quant_scale: min(8, quant_scale) up to 16, then
// quant_scale / 2 capped at 16. Part of the bitstream contract.
int intra_dc_step(int quant_scale);

struct Quantizer {
  BlockKind kind = BlockKind::kIntra;
  int quant_scale = 8;
  // coefficient = sign(level) * ((|level| * scale[i] + 8) >> 4), i in natural order.
  // scale[i] = W[i] * quant_scale, except intra DC: 16 * intra_dc_step(quant_scale).
  std::array<int32_t, 64> scale{};
  // Encoder only: 16 / scale[i] and the rounding offsets (fractions of a step added
  // before truncation; 0.5 is plain rounding, smaller values widen the dead zone).
  std::array<float, 64> inverse_step{};
  float rounding_dc = 0.5f;
  float rounding_ac = 0.5f;
};

// quant_scale is clamped to [1, 112].
Quantizer make_quantizer(BlockKind kind, int quant_scale);

// Quantizes DCT coefficients (natural order) to levels in [-kMaxLevel, kMaxLevel].
// Returns the number of non-zero levels.
int quantize_block(const Quantizer& quantizer, const float* coefficients, int16_t* levels);

// Exact integer dequantization of one level at natural position `index`, saturated to
// [kMinCoefficient, kMaxCoefficient].
int dequantize_level(const Quantizer& quantizer, int index, int level);
void dequantize_block(const Quantizer& quantizer, const int16_t* levels, int16_t* coefficients);

// Forward DCT + quantization of one block of samples (intra: pixel - 128; non-intra:
// residual). Returns the number of non-zero levels.
int transform_quantize_block(const Quantizer& quantizer, const int16_t* samples, int16_t* levels);

// Dequantization + integer inverse DCT: what the decoder reconstructs, before the caller
// adds 128 (intra) or the prediction (non-intra) and clips to [0, 255].
void dequantize_inverse_transform_block(const Quantizer& quantizer, const int16_t* levels, int16_t* samples);

}  // namespace svc::codec
