// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "codec/common/coefficient_contexts.h"
#include "codec/common/dct.h"
#include "codec/common/intra_frame.h"
#include "codec/common/quant.h"
#include "codec/decoder/coefficient_reader.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/coefficient_writer.h"
#include "codec/encoder/forward_transform.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/quantize.h"
#include "codec/encoder/range_encoder.h"
#include "codec/encoder/rdoq.h"

namespace svc::codec {
namespace {

// DCT coefficients of a random block: a smooth ramp plus noise of random strength, like
// prediction residuals (non-intra) or pixels around 128 (intra).
void random_coefficients(std::mt19937& rng, float* coefficients) {
  std::normal_distribution<float> noise(0.0f, 1.0f);
  const float strength = static_cast<float>(1 + rng() % 40);
  const float slope_x = noise(rng) * 4, slope_y = noise(rng) * 4;
  float samples[64];
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) samples[8 * y + x] = slope_x * x + slope_y * y + strength * noise(rng);
  }
  forward_dct_8x8(samples, coefficients);
}

// Contexts in a state an encoder would meet: adapted to a few hundred blocks.
BlockContextSet trained_contexts(std::mt19937& rng, const Quantizer& quantizer) {
  BlockContextSet set;
  std::vector<uint8_t> bytes;
  RangeEncoder encoder(&bytes);
  for (int n = 0; n < 300; ++n) {
    float coefficients[64];
    int16_t levels[64];
    random_coefficients(rng, coefficients);
    quantize_block(quantizer, coefficients, levels);
    encode_block_levels(encoder, set, levels, n % kCodedBlockContexts);
  }
  return set;
}

struct Case {
  ResidualMatrix matrix;
  int coded_block_context;
};

TEST(CodecRdoq, NeverCostsMoreThanPlainQuantizationAndUsuallyLess) {
  std::mt19937 rng(31);
  const Case cases[] = {{ResidualMatrix::kFlat, 1},
                        {ResidualMatrix::kFlat, kNoCodedBlockFlag},
                        {ResidualMatrix::kWeighted, 0}};
  for (const Case& c : cases) {
    for (int qindex : {64, 115, 160, 202}) {  // quantizer scales about 2, 6, 16 and 40
      const Quantizer quantizer = make_residual_quantizer(TransformSize::k8x8, qindex, c.matrix);
      const BlockContextSet contexts = trained_contexts(rng, quantizer);
      const double scale = quantizer_scale_q8(qindex) / 256.0;
      const float lambda = static_cast<float>(0.25 * scale * scale);
      double plain_total = 0, rdoq_total = 0;
      for (int n = 0; n < 300; ++n) {
        float coefficients[64];
        random_coefficients(rng, coefficients);
        int16_t plain[64], optimized[64];
        quantize_block(quantizer, coefficients, plain);
        const int nonzero =
            rdoq_quantize_block(quantizer, coefficients, contexts, c.coded_block_context, lambda, optimized);
        ASSERT_EQ(nonzero, std::count_if(optimized, optimized + 64, [](int16_t v) { return v != 0; }));
        for (int i = 0; i < 64; ++i) ASSERT_LE(std::abs(optimized[i]), kMaxLevel);
        const double plain_cost =
            quantization_rd_cost(quantizer, coefficients, plain, contexts, c.coded_block_context, lambda);
        const double rdoq_cost =
            quantization_rd_cost(quantizer, coefficients, optimized, contexts, c.coded_block_context, lambda);
        ASSERT_LE(rdoq_cost, plain_cost * (1 + 1e-6) + 1e-3)
            << "qindex " << qindex << " case " << (&c - cases) << " block " << n;
        plain_total += plain_cost;
        rdoq_total += rdoq_cost;
      }
      // The search itself (not just the fallback to plain levels) must find savings.
      EXPECT_LT(rdoq_total, plain_total * 0.98) << "qindex " << qindex << " case " << (&c - cases);
    }
  }
}

TEST(CodecRdoq, ZeroLambdaKeepsTheNearestLevels) {
  std::mt19937 rng(32);
  const Quantizer quantizer = make_residual_quantizer(TransformSize::k8x8, 128);  // quantizer scale 8
  Quantizer nearest = quantizer;
  nearest.rounding_dc = nearest.rounding_ac = 0.5f;
  const BlockContextSet contexts;
  for (int n = 0; n < 200; ++n) {
    float coefficients[64];
    random_coefficients(rng, coefficients);
    int16_t rounded[64], optimized[64];
    quantize_block(nearest, coefficients, rounded);
    rdoq_quantize_block(quantizer, coefficients, contexts, 0, 0.0f, optimized);
    // Without a rate term only the squared error counts: nearest rounding is optimal.
    double rounded_error = 0, optimized_error = 0;
    for (int i = 0; i < 64; ++i) {
      rounded_error += std::pow(coefficients[i] - dequantize_level(quantizer, i, rounded[i]), 2);
      optimized_error += std::pow(coefficients[i] - dequantize_level(quantizer, i, optimized[i]), 2);
    }
    ASSERT_NEAR(optimized_error, rounded_error, 1e-3 * (1 + rounded_error)) << "block " << n;
  }
}

TEST(CodecRdoq, LargeLambdaEmptiesWeakBlocks) {
  std::mt19937 rng(33);
  const Quantizer quantizer = make_residual_quantizer(TransformSize::k8x8, 128);  // quantizer scale 8
  const BlockContextSet contexts;
  float coefficients[64] = {};
  coefficients[kZigZag[40]] = 10.0f;  // rounds to level 1, far down the scan
  int16_t levels[64];
  EXPECT_EQ(rdoq_quantize_block(quantizer, coefficients, contexts, 0, 1.0f, levels), 1);
  EXPECT_EQ(levels[kZigZag[40]], 1);
  EXPECT_EQ(rdoq_quantize_block(quantizer, coefficients, contexts, 0, 1000.0f, levels), 0);
}

// A textured frame: gradients, a few sinusoids and noise, in all three planes.
ImageYCbCr420 textured_frame(int width, int height) {
  std::mt19937 rng(34);
  std::normal_distribution<double> noise(0.0, 6.0);
  auto plane = [&](int w, int h, double phase) {
    std::vector<uint8_t> samples(static_cast<size_t>(w) * h);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const double value = 110 + 0.4 * x - 0.3 * y + 40 * std::sin(0.21 * x + phase) * std::cos(0.13 * y) +
                             20 * std::sin(0.9 * (x + y)) + noise(rng);
        samples[static_cast<size_t>(y) * w + x] = static_cast<uint8_t>(std::clamp(value, 0.0, 255.0));
      }
    }
    return samples;
  };
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  image.y = plane(width, height, 0);
  image.cb = plane(width / 2, height / 2, 1);
  image.cr = plane(width / 2, height / 2, 2);
  return image;
}

double squared_error(const ImageYCbCr420& a, const ImageYCbCr420& b) {
  double sum = 0;
  for (const auto& [p, q] : {std::pair{&a.y, &b.y}, std::pair{&a.cb, &b.cb}, std::pair{&a.cr, &b.cr}}) {
    for (size_t i = 0; i < p->size(); ++i) sum += std::pow(double((*p)[i]) - double((*q)[i]), 2);
  }
  return sum;
}

// On a whole intra frame: the decoder reproduces the encoder's reconstruction with and
// without RDOQ, and RDOQ lowers the frame's squared error + lambda * bits.
TEST(CodecRdoq, IntraFramesDecodeExactlyAndCostLess) {
  const ImageYCbCr420 source = textured_frame(128, 96);
  for (int qindex : {83, 138, 179}) {  // quantizer scales about 3, 10 and 24
    const double scale = quantizer_scale_q8(qindex) / 256.0;
    double cost[2];
    for (bool rdoq : {false, true}) {
      CodingParams params;
      params.qindex = qindex;
      params.rdoq = rdoq;
      params.deblocking = params.cdef = false;  // the levels alone
      params.transform_sizes = false;           // of one size
      ImageYCbCr420 reconstruction, decoded;
      const std::vector<uint8_t> bytes = encode_intra_frame(source, params, &reconstruction);
      ASSERT_TRUE(decode_intra_frame(bytes, source.width, source.height, &decoded).ok());
      ASSERT_EQ(decoded.y, reconstruction.y) << qindex;
      ASSERT_EQ(decoded.cb, reconstruction.cb) << qindex;
      ASSERT_EQ(decoded.cr, reconstruction.cr) << qindex;
      cost[rdoq] = squared_error(source, reconstruction) + 0.1 * scale * scale * 8.0 * bytes.size();
    }
    EXPECT_LT(cost[1], cost[0]) << "qindex " << qindex;
  }
}

}  // namespace
}  // namespace svc::codec
