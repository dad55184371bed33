#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>

#include "codec/dct.h"
#include "codec/quant.h"

namespace svc::codec {
namespace {

TEST(CodecQuant, DefaultMatricesAreMpeg2) {
  EXPECT_EQ(kDefaultIntraMatrix[0], 8);
  EXPECT_EQ(kDefaultIntraMatrix[1], 16);
  EXPECT_EQ(kDefaultIntraMatrix[8], 16);
  EXPECT_EQ(kDefaultIntraMatrix[63], 83);
  EXPECT_EQ(kDefaultIntraMatrix[7], 34);
  for (int w : kDefaultNonIntraMatrix) EXPECT_EQ(w, 16);
}

TEST(CodecQuant, IntraDcStep) {
  EXPECT_EQ(intra_dc_step(1), 1);
  EXPECT_EQ(intra_dc_step(4), 4);
  EXPECT_EQ(intra_dc_step(8), 8);
  EXPECT_EQ(intra_dc_step(16), 8);
  EXPECT_EQ(intra_dc_step(20), 10);
  EXPECT_EQ(intra_dc_step(112), 16);
}

TEST(CodecQuant, DequantizationIsTheDocumentedIntegerFormula) {
  const Quantizer intra = make_quantizer(BlockKind::kIntra, 5);
  EXPECT_EQ(intra.scale[0], 16 * 5);
  EXPECT_EQ(dequantize_level(intra, 0, 3), 15);     // DC: level * dc step
  EXPECT_EQ(dequantize_level(intra, 1, 1), 5);      // (16*5 + 8) >> 4
  EXPECT_EQ(dequantize_level(intra, 63, -2), -52);  // (2*83*5 + 8) >> 4 = 52
  EXPECT_EQ(dequantize_level(intra, 63, 4095), kMaxCoefficient);
  EXPECT_EQ(dequantize_level(intra, 63, -4095), kMinCoefficient);
  const Quantizer non_intra = make_quantizer(BlockKind::kNonIntra, 3);
  EXPECT_EQ(dequantize_level(non_intra, 0, 7), 21);
  EXPECT_EQ(dequantize_level(non_intra, 9, -1), -3);
  EXPECT_EQ(make_quantizer(BlockKind::kIntra, 500).quant_scale, 112);
  EXPECT_EQ(make_quantizer(BlockKind::kIntra, 0).quant_scale, 1);
}

TEST(CodecQuant, QuantizationErrorIsBoundedByTheStep) {
  std::mt19937 rng(5);
  for (BlockKind kind : {BlockKind::kIntra, BlockKind::kNonIntra}) {
    for (int qs : {1, 2, 8, 31, 112}) {
      const Quantizer q = make_quantizer(kind, qs);
      for (int n = 0; n < 200; ++n) {
        float coefficients[64];
        int16_t levels[64], back[64];
        for (float& c : coefficients) c = static_cast<float>(static_cast<int>(rng() % 3000) - 1500) / 1.5f;
        quantize_block(q, coefficients, levels);
        dequantize_block(q, levels, back);
        for (int i = 0; i < 64; ++i) {
          ASSERT_LE(std::abs(levels[i]), kMaxLevel);
          const double step = q.scale[i] / 16.0;
          const double rounding = i == 0 ? q.rounding_dc : q.rounding_ac;
          // Truncation after adding `rounding` steps, plus half a unit of integer rounding.
          const double bound = std::max(rounding, 1.0 - rounding) * step + 0.5 + 1e-3;
          ASSERT_LE(std::fabs(back[i] - coefficients[i]), bound)
              << "qs " << qs << " position " << i << " level " << levels[i];
        }
      }
    }
  }
}

TEST(CodecQuant, NonIntraDeadZoneDropsSmallResiduals) {
  const Quantizer q = make_quantizer(BlockKind::kNonIntra, 8);  // step 8
  float coefficients[64] = {};
  coefficients[0] = 6.0f;   // 0.75 step: below 1 - 0.2
  coefficients[5] = -6.3f;  // also dropped
  coefficients[9] = 7.0f;   // 0.875 step + 0.2 >= 1: kept
  int16_t levels[64];
  EXPECT_EQ(quantize_block(q, coefficients, levels), 1);
  EXPECT_EQ(levels[9], 1);
}

TEST(CodecQuant, BlockTransformRoundTripAtFinestScaleIsNearLossless) {
  std::mt19937 rng(9);
  for (BlockKind kind : {BlockKind::kIntra, BlockKind::kNonIntra}) {
    const Quantizer q = make_quantizer(kind, 1);
    double squared = 0;
    int peak = 0;
    for (int n = 0; n < 200; ++n) {
      int16_t samples[64], levels[64], back[64];
      // White noise: the worst case for the coarse high-frequency steps of the intra matrix.
      for (int16_t& s : samples) s = static_cast<int16_t>(static_cast<int>(rng() % 256) - 128);
      transform_quantize_block(q, samples, levels);
      dequantize_inverse_transform_block(q, levels, back);
      for (int i = 0; i < 64; ++i) {
        const int error = back[i] - samples[i];
        peak = std::max(peak, std::abs(error));
        squared += error * error;
      }
    }
    EXPECT_LE(peak, 5);
    EXPECT_LT(std::sqrt(squared / (200 * 64)), kind == BlockKind::kIntra ? 1.3 : 0.6);
  }
}

}  // namespace
}  // namespace svc::codec
