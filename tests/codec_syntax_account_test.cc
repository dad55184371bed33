// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "codec/encoder/bframe_encoder.h"
#include "codec/encoder/bit_cost.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/range_encoder.h"
#include "codec/encoder/syntax_account.h"
#include "support/reference_hints.h"

namespace svc::codec {
namespace {

// A smooth texture with detail, deterministic per seed: image(x, y) = texture(x + ox, y + oy).
ImageYCbCr420 textured(int width, int height, int ox, int oy) {
  auto value = [](int x, int y, double scale) {
    return 128 + 60 * std::sin(x * 0.11 * scale + std::cos(y * 0.07)) * std::cos(y * 0.09 * scale) +
           25 * std::sin((x + 2 * y) * 0.31);
  };
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  image.y.resize(static_cast<size_t>(width) * height);
  image.cb.resize(static_cast<size_t>(cw) * ch);
  image.cr.resize(image.cb.size());
  std::mt19937 rng(5);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double v = value(x + ox, y + oy, 1.0) + static_cast<double>(rng() % 7) - 3;
      image.y[static_cast<size_t>(y) * width + x] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 255.0)));
    }
  }
  for (int y = 0; y < ch; ++y) {
    for (int x = 0; x < cw; ++x) {
      const double v = 0.5 * value(2 * x + ox, 2 * y + oy, 0.5) + 64;
      image.cb[static_cast<size_t>(y) * cw + x] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 255.0)));
      image.cr[static_cast<size_t>(y) * cw + x] =
          static_cast<uint8_t>(255 - image.cb[static_cast<size_t>(y) * cw + x]);
    }
  }
  return image;
}

void expect_sum_near_payload(const SyntaxBits& syntax, size_t payload_bytes) {
  const double bits = syntax.total(), payload_bits = 8.0 * static_cast<double>(payload_bytes);
  EXPECT_NEAR(bits, payload_bits, 0.01 * payload_bits + 8 * 8) << "payload " << payload_bytes << " bytes";
  for (double b : syntax.bits) EXPECT_GE(b, 0);
}

TEST(SyntaxAccount, NamesCoverEveryElement) {
  EXPECT_STREQ(syntax_element_name(SyntaxElement::kHeader), "header");
  EXPECT_STREQ(syntax_element_name(SyntaxElement::kModes), "modes");
  EXPECT_STREQ(syntax_element_name(SyntaxElement::kPartitions), "partitions");
  EXPECT_STREQ(syntax_element_name(SyntaxElement::kVectors), "vectors");
  EXPECT_STREQ(syntax_element_name(SyntaxElement::kLevels), "levels");
  EXPECT_STREQ(syntax_element_name(SyntaxElement::kFilters), "filters");
  EXPECT_EQ(static_cast<size_t>(SyntaxElement::kFilters) + 1, kSyntaxElements);
}

TEST(SyntaxAccount, ScopesNestAndTheAccountLeavesTheBytesAlone) {
  std::vector<uint8_t> plain_bytes, counted_bytes;
  RangeEncoder plain(&plain_bytes), counted(&counted_bytes);
  SyntaxBits account;
  counted.set_account(&account);
  AdaptiveBit plain_model, counted_model;
  std::mt19937 rng(3);
  double expected_modes = 0;
  for (int i = 0; i < 2000; ++i) {
    const int bit = (rng() % 8) == 0;
    const SyntaxScope modes(counted, SyntaxElement::kModes);
    expected_modes += bit_cost(counted_model, bit);
    plain.encode(plain_model, bit);
    counted.encode(counted_model, bit);
    {
      const SyntaxScope levels(counted, SyntaxElement::kLevels);
      EXPECT_EQ(account.current, SyntaxElement::kLevels);
      plain.encode_bypass(bit);
      counted.encode_bypass(bit);
    }
    EXPECT_EQ(account.current, SyntaxElement::kModes);
  }
  EXPECT_EQ(account.current, SyntaxElement::kHeader);
  plain.finish();
  counted.finish();
  EXPECT_EQ(plain_bytes, counted_bytes);
  EXPECT_DOUBLE_EQ(account.of(SyntaxElement::kLevels), 2000);
  EXPECT_NEAR(account.of(SyntaxElement::kModes), expected_modes, 1e-6 * expected_modes);
  EXPECT_EQ(account.of(SyntaxElement::kHeader), 0);
  // A scope on an encoder without an account does nothing.
  const SyntaxScope nothing(plain, SyntaxElement::kVectors);
  EXPECT_EQ(plain.account(), nullptr);
}

TEST(SyntaxAccount, IntraFrameBitsSumToItsPayload) {
  const ImageYCbCr420 source = textured(96, 80, 0, 0);
  CodingParams params;
  params.qindex = 80;
  SyntaxBits syntax;
  ImageYCbCr420 counted_reconstruction, plain_reconstruction;
  const std::vector<uint8_t> counted = encode_intra_frame(source, params, &counted_reconstruction, &syntax);
  const std::vector<uint8_t> plain = encode_intra_frame(source, params, &plain_reconstruction);
  ASSERT_FALSE(counted.empty());
  EXPECT_EQ(counted, plain);
  EXPECT_EQ(counted_reconstruction.y, plain_reconstruction.y);
  expect_sum_near_payload(syntax, counted.size());
  EXPECT_GT(syntax.of(SyntaxElement::kLevels), 0);
  EXPECT_GT(syntax.of(SyntaxElement::kModes), 0);
  EXPECT_GT(syntax.of(SyntaxElement::kPartitions), 0);
  EXPECT_GE(syntax.of(SyntaxElement::kHeader), 8.0 * 3);
  EXPECT_EQ(syntax.of(SyntaxElement::kVectors), 0);
}

TEST(SyntaxAccount, BFrameBitsSumToItsPayloadAndCountVectors) {
  const int w = 128, h = 96, q = 120;
  ImageYCbCr420 ref0, ref1;
  encode_intra_frame(textured(w, h, 40, 40), CodingParams{q - 42}, &ref0);
  encode_intra_frame(textured(w, h, 46, 40), CodingParams{q - 42}, &ref1);
  const ImageYCbCr420 source = textured(w, h, 43, 41);
  const size_t macroblocks = static_cast<size_t>((w + 15) / 16) * ((h + 15) / 16);
  const FaceCandidates c0(macroblocks, {MotionVector{12, 4}, MotionVector{0, 0}, MotionVector{8, 4}});
  const FaceCandidates c1(macroblocks, {MotionVector{-12, 4}, MotionVector{0, 0}, MotionVector{-8, 4}});
  BFrameParams params;
  params.qindex = q;
  BFrameStats stats;
  ImageYCbCr420 counted_reconstruction, plain_reconstruction;
  const std::vector<uint8_t> counted =
      encode_b_frame(source, ref0, &ref1, candidate_hints(c0, c1), params, &counted_reconstruction, &stats);
  const std::vector<uint8_t> plain =
      encode_b_frame(source, ref0, &ref1, candidate_hints(c0, c1), params, &plain_reconstruction, nullptr);
  ASSERT_FALSE(counted.empty());
  EXPECT_EQ(counted, plain);
  EXPECT_EQ(counted_reconstruction.y, plain_reconstruction.y);
  const SyntaxBits& syntax = stats.syntax;
  expect_sum_near_payload(syntax, counted.size());
  EXPECT_GT(syntax.of(SyntaxElement::kLevels), 0);
  EXPECT_GT(syntax.of(SyntaxElement::kModes), 0);
  EXPECT_GT(syntax.of(SyntaxElement::kVectors), 0);
  EXPECT_GE(syntax.of(SyntaxElement::kHeader), 8.0 * kBFrameHeaderBytes);
}

}  // namespace
}  // namespace svc::codec
