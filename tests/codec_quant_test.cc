// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>

#include "codec/common/dct.h"
#include "codec/common/quant.h"
#include "codec/encoder/quantize.h"

namespace svc::codec {
namespace {

TEST(CodecQuant, DefaultIntraMatrixIsMpeg2s) {
  EXPECT_EQ(kDefaultIntraMatrix[0], 8);
  EXPECT_EQ(kDefaultIntraMatrix[1], 16);
  EXPECT_EQ(kDefaultIntraMatrix[8], 16);
  EXPECT_EQ(kDefaultIntraMatrix[63], 83);
  EXPECT_EQ(kDefaultIntraMatrix[7], 34);
}

TEST(CodecQuant, ScaleDoublesEvery32Indices) {
  EXPECT_EQ(quantizer_scale_q8(0), 128);  // MPEG-2 quantizer_scale 0.5
  EXPECT_EQ(quantizer_scale_q8(1), 131);
  EXPECT_EQ(quantizer_scale_q8(31), 251);
  EXPECT_EQ(quantizer_scale_q8(32), 256);  // 1
  EXPECT_EQ(quantizer_scale_q8(128), 2048);
  EXPECT_EQ(quantizer_scale_q8(255), 251 << 7);
  EXPECT_EQ(quantizer_scale_q8(-3), 128);  // clamped
  EXPECT_EQ(quantizer_scale_q8(300), 251 << 7);
  for (int q = 1; q <= kMaxQIndex; ++q) {
    EXPECT_GT(quantizer_scale_q8(q), quantizer_scale_q8(q - 1)) << q;
    const double expected = 128.0 * std::pow(2.0, q / 32.0);
    EXPECT_NEAR(quantizer_scale_q8(q) / expected, 1.0, 0.01) << q;
  }
}

TEST(CodecQuant, FlatStepsAreTheScale) {
  // (16 * scale + 8) >> 4 in 1/256 units; scale 2048 (index 128) is MPEG-2's scale 8.
  EXPECT_EQ(residual_step(TransformSize::k8x8, 128), 2048);
  EXPECT_EQ(residual_step(TransformSize::k4x4, 1), (16 * 131 + 8) >> 4);
  for (int qindex = kMinQIndex; qindex <= kMaxQIndex; ++qindex) {
    EXPECT_EQ(residual_step(TransformSize::k8x8, qindex), quantizer_scale_q8(qindex)) << qindex;
  }
  const Quantizer q = make_residual_quantizer(TransformSize::k8x8, 77);
  for (int i = 0; i < 64; ++i) EXPECT_EQ(q.scale[i], quantizer_scale_q8(77)) << i;
}

TEST(CodecQuant, DequantizationIsTheDocumentedIntegerFormula) {
  // Weighted 8x8 steps at index 106 (about MPEG-2's scale 5): DC 1272, AC (W * 1272 + 8) >> 4.
  const Quantizer weighted = make_residual_quantizer(TransformSize::k8x8, 106, ResidualMatrix::kWeighted);
  EXPECT_EQ(quantizer_scale_q8(106), 159 << 3);  // T[10] << 3 = 1272
  EXPECT_EQ(weighted.scale[0], 1272);
  EXPECT_EQ(dequantize_level(weighted, 0, 3), 15);     // (3 * 1272 + 128) >> 8
  EXPECT_EQ(dequantize_level(weighted, 1, 1), 5);      // (1 * 1272 + 128) >> 8
  EXPECT_EQ(dequantize_level(weighted, 63, -2), -52);  // (2 * 6599 + 128) >> 8 = 52
  EXPECT_EQ(dequantize_level(weighted, 63, 4095), kMaxCoefficient);
  EXPECT_EQ(dequantize_level(weighted, 63, -4095), kMinCoefficient);
  const Quantizer fine = make_residual_quantizer(TransformSize::k8x8, 0);  // step 0.5
  EXPECT_EQ(dequantize_level(fine, 0, 7), 4);                              // 3.5 rounds up
  EXPECT_EQ(dequantize_level(fine, 9, -1), -1);
  EXPECT_EQ(dequantize_level(fine, 9, 4095), 2047);
  EXPECT_EQ(make_residual_quantizer(TransformSize::k8x8, 500).qindex, kMaxQIndex);
  EXPECT_EQ(make_residual_quantizer(TransformSize::k8x8, -1).qindex, kMinQIndex);
}

TEST(CodecQuant, QuantizationErrorIsBoundedByTheStep) {
  std::mt19937 rng(5);
  for (ResidualMatrix matrix : {ResidualMatrix::kWeighted, ResidualMatrix::kFlat}) {
    for (int qs : {0, 32, 64, 128, 200, 255}) {
      const Quantizer q = make_residual_quantizer(TransformSize::k8x8, qs, matrix);
      for (int n = 0; n < 200; ++n) {
        float coefficients[64];
        int16_t levels[64], back[64];
        for (float& c : coefficients) c = static_cast<float>(static_cast<int>(rng() % 3000) - 1500) / 1.5f;
        quantize_block(q, coefficients, levels);
        dequantize_block(q, levels, back);
        for (int i = 0; i < 64; ++i) {
          ASSERT_LE(std::abs(levels[i]), kMaxLevel);
          if (std::abs(levels[i]) == kMaxLevel) continue;  // capped: the bound does not hold
          const double step = q.scale[i] / 256.0;
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
  const Quantizer q = make_residual_quantizer(TransformSize::k8x8, 128);  // step 8
  float coefficients[64] = {};
  coefficients[0] = 6.0f;   // 0.75 step: below 1 - 0.2
  coefficients[5] = -6.3f;  // also dropped
  coefficients[9] = 7.0f;   // 0.875 step + 0.2 >= 1: kept
  int16_t levels[64];
  EXPECT_EQ(quantize_block(q, coefficients, levels), 1);
  EXPECT_EQ(levels[9], 1);
}

// Blocks smaller than the 8x8 kernels quantize and dequantize their own samples only:
// what lies past them in the caller's arrays is neither read, written nor counted.
TEST(CodecQuant, BlocksSmallerThan8x8StayInsideTheirArea) {
  for (TransformSize size : {TransformSize::k4x4, TransformSize::k8x4, TransformSize::k4x8}) {
    const int area = transform_area(size);
    SCOPED_TRACE(area);
    const Quantizer q = make_residual_quantizer(size, 100);
    float coefficients[64];
    std::fill_n(coefficients, 64, 5000.0f);  // past the block: would quantize to large levels
    std::fill_n(coefficients, area, 0.0f);
    coefficients[1] = 300.0f;
    int16_t levels[64];
    std::fill_n(levels, 64, int16_t{-7});
    EXPECT_EQ(quantize_block(q, coefficients, levels), 1);
    EXPECT_EQ(quantize_block_nearest(q, coefficients, levels), 1);
    EXPECT_GT(levels[1], 0);
    EXPECT_TRUE(std::all_of(levels + area, levels + 64, [](int16_t v) { return v == -7; }));
    std::fill_n(levels + area, 64 - area, int16_t{1000});
    int16_t dequantized[64];
    std::fill_n(dequantized, 64, int16_t{-9});
    dequantize_block(q, levels, dequantized);
    EXPECT_EQ(dequantized[0], 0);
    EXPECT_GT(dequantized[1], 0);
    EXPECT_TRUE(std::all_of(dequantized + area, dequantized + 64, [](int16_t v) { return v == -9; }));
  }
}

TEST(CodecQuant, BlockTransformRoundTripAtMpeg2sFinestScaleIsNearLossless) {
  std::mt19937 rng(9);
  for (ResidualMatrix matrix : {ResidualMatrix::kWeighted, ResidualMatrix::kFlat}) {
    const Quantizer q = make_residual_quantizer(TransformSize::k8x8, 32, matrix);  // MPEG-2's quantizer_scale 1
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
    EXPECT_LT(std::sqrt(squared / (200 * 64)), matrix == ResidualMatrix::kWeighted ? 1.3 : 0.6);
  }
}

TEST(CodecQuant, WeightedResidualStepsFollowTheDocumentedMatrix) {
  for (int qindex : {0, 64, 129, 255}) {
    for (TransformSize size : {TransformSize::k4x4, TransformSize::k8x8, TransformSize::k16x16}) {
      const int width = transform_width(size);
      const int flat = residual_step(size, qindex);
      const Quantizer weighted = make_residual_quantizer(size, qindex, ResidualMatrix::kWeighted);
      const Quantizer plain = make_residual_quantizer(size, qindex);
      for (int i = 0; i < transform_area(size); ++i) {
        EXPECT_EQ(plain.scale[static_cast<size_t>(i)], flat);
        const int r = i / width, c = i % width;
        const int r8 = width == 16 ? r / 2 : width == 4 ? 2 * r : r;
        const int c8 = width == 16 ? c / 2 : width == 4 ? 2 * c : c;
        const int w = r8 == 0 && c8 == 0 ? 16 : kDefaultIntraMatrix[static_cast<size_t>(8 * r8 + c8)];
        EXPECT_EQ(residual_weight(size, i), w);
        EXPECT_EQ(weighted.scale[static_cast<size_t>(i)], std::max((flat * w + 8) >> 4, 128));
      }
    }
  }
  // The DC keeps the flat step; the highest 8x8 frequency is 83/16 times coarser.
  EXPECT_EQ(residual_step(TransformSize::k8x8, 100, ResidualMatrix::kWeighted, 0),
            residual_step(TransformSize::k8x8, 100));
  EXPECT_GT(residual_step(TransformSize::k8x8, 100, ResidualMatrix::kWeighted, 63),
            5 * residual_step(TransformSize::k8x8, 100));
}

}  // namespace
}  // namespace svc::codec
