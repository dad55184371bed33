// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/epipolar.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "codec/common/bframe.h"
#include "codec/common/integer_division.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/decoder/bframe_syntax_reader.h"
#include "codec/decoder/range_decoder.h"
#include "codec/encoder/bframe_encoder.h"
#include "codec/encoder/bframe_syntax_writer.h"
#include "codec/encoder/coefficient_writer.h"
#include "codec/encoder/range_encoder.h"

namespace svc::codec {
namespace {

// The double-precision floor division equals the integer one bit for bit: at the
// boundaries of its exact range, around every multiple (where a rounded quotient could
// land on the next integer), and on random operands of every magnitude.
TEST(CodecEpipolar, FloorDivisionEqualsTheIntegerReference) {
  constexpr int64_t kExact = int64_t{1} << 52;
  std::vector<int64_t> numerators = {
      0, 1, -1, kExact - 1, -(kExact - 1), kExact, -kExact, INT64_MAX / 2, INT64_MIN / 2};
  std::vector<int64_t> divisors = {1, 2, 3, 7, 1 << 20, kExact - 1, kExact, kExact + 1, INT64_MAX / 4};
  std::mt19937_64 rng(11);
  for (int bits = 1; bits <= 62; ++bits) {
    for (int k = 0; k < 200; ++k) {
      const int64_t magnitude = static_cast<int64_t>(rng() >> (64 - bits));
      numerators.push_back(k % 2 ? magnitude : -magnitude);
      divisors.push_back(std::max<int64_t>(1, static_cast<int64_t>(rng() >> (64 - bits))));
    }
  }
  int64_t checked = 0;
  for (size_t i = 0; i < divisors.size(); ++i) {
    const int64_t b = divisors[i];
    for (int64_t a : {numerators[i % numerators.size()], numerators[(i * 7 + 3) % numerators.size()]}) {
      ASSERT_EQ(floor_divide(a, b), floor_divide_reference(a, b)) << a << " / " << b;
      ++checked;
    }
    // Around multiples of b, where the quotient is an integer or just below one.
    for (const int64_t q : {int64_t{0}, int64_t{1}, int64_t{-1}, int64_t{12345}, int64_t{-98765}}) {
      if (b > kExact / 100000) break;
      for (int64_t d = -2; d <= 2; ++d) {
        const int64_t a = q * b + d;
        ASSERT_EQ(floor_divide(a, b), floor_divide_reference(a, b)) << a << " / " << b;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 50000);
  EXPECT_EQ(floor_divide(-7, 2), -4);
  EXPECT_EQ(floor_divide(7, 2), 3);
  EXPECT_EQ(floor_divide(-6, 3), -2);
}

TEST(CodecEpipolar, LineCoordinatesAreABijectionOnIntegerVectors) {
  std::mt19937 rng(5);
  const std::vector<LineDirection> directions = {{0, 0},  {5, 0},  {0, -7},    {3, 3},
                                                 {-4, 4}, {9, -2}, {-1, -100}, {1 << 27, -(1 << 26)}};
  for (const LineDirection d : directions) {
    for (int n = 0; n < 2000; ++n) {
      const int64_t x = static_cast<int64_t>(rng() % 65535) - 32767,
                    y = static_cast<int64_t>(rng() % 65535) - 32767;
      const LineCoordinates c = to_line_coordinates(x, y, d);
      int64_t bx = 0, by = 0;
      from_line_coordinates(c, d, &bx, &by);
      ASSERT_EQ(bx, x);
      ASSERT_EQ(by, y);
    }
  }
  EXPECT_EQ(to_line_coordinates(3, -9, {0, 0}).along, 3);
  EXPECT_EQ(to_line_coordinates(3, -9, {0, 0}).across, -9);
}

TEST(CodecEpipolar, VectorsOnTheLineHaveNoAcrossComponent) {
  // Along the major axis the vector moves with `along`; on the minor axis it is the
  // quarter-pel point nearest the line, and a positive `along` points the direction's way.
  for (const LineDirection d : std::vector<LineDirection>{{12, 5}, {-12, 5}, {5, -12}, {-7, -7}, {300, -1}}) {
    for (int64_t along = -40; along <= 40; ++along) {
      int64_t x = 0, y = 0;
      from_line_coordinates({along, 0}, d, &x, &y);
      const bool x_major = std::llabs(d.x) >= std::llabs(d.y);
      const double exact = x_major ? static_cast<double>(along) * d.y / std::llabs(d.x)
                                   : static_cast<double>(along) * d.x / std::llabs(d.y);
      EXPECT_LE(std::abs(static_cast<double>(x_major ? y : x) - exact), 0.5);
      EXPECT_EQ(x_major ? x : y, along * ((x_major ? d.x : d.y) > 0 ? 1 : -1));
      if (along > 0) EXPECT_GT(x * d.x + y * d.y, 0);
      EXPECT_EQ(to_line_coordinates(x, y, d).across, 0);
    }
  }
}

TEST(CodecEpipolar, DirectionsFollowTheDocumentedField) {
  const EpipolarLines lines{1, -1, 0};
  // 64 x 32 face: epipole at the right edge's middle, (64, 16) in pixel-edge coordinates.
  EXPECT_EQ(line_direction(lines, 64, 32, 2 * 8, 2 * 16).x, 16 - 128);
  EXPECT_EQ(line_direction(lines, 64, 32, 2 * 8, 2 * 16).y, 0);
  EXPECT_EQ(line_direction(lines, 64, 32, 2 * 64, 2 * 4).x, 0);
  EXPECT_EQ(line_direction(lines, 64, 32, 2 * 64, 2 * 4).y, 8 - 32);
  EXPECT_EQ(line_direction(EpipolarLines{0, 2, -3}, 10, 20, 7, 9).x, 20);
  EXPECT_EQ(line_direction(EpipolarLines{0, 2, -3}, 10, 20, 7, 9).y, -60);
}

TEST(CodecEpipolar, CarryingKeepsTheDepthAcrossDirections) {
  // One depth: the motion is the same multiple (here 1/5) of the direction everywhere.
  int64_t x = 0, y = 0;
  ASSERT_TRUE(carry_along_lines(8, 6, {40, 30}, {-20, 50}, &x, &y));
  EXPECT_EQ(x, -4);
  EXPECT_EQ(y, 10);
  // Directions beyond 2^15 are shifted alike: the same result at 2^12 times the scale.
  ASSERT_TRUE(carry_along_lines(8, 6, {40 << 12, 30 << 12}, {-20 << 12, 50 << 12}, &x, &y));
  EXPECT_EQ(x, -4);
  EXPECT_EQ(y, 10);
  // A vector off the line carries its projection; the result lies on the new line.
  ASSERT_TRUE(carry_along_lines(9, 5, {40, 30}, {50, -20}, &x, &y));
  EXPECT_EQ(to_line_coordinates(x, y, {50, -20}).across, 0);
  EXPECT_EQ(x, 10);  // t = (9*40 + 5*30) / 2500 = 0.204, 0.204 * 50 = 10.2
  // Nodes of large faces (2^17 eighth-pels) with the largest directions do not overflow.
  ASSERT_TRUE(carry_along_lines(1 << 17, -(1 << 17), {1 << 27, -(1 << 27)}, {1 << 27, -(1 << 27)}, &x, &y));
  EXPECT_EQ(x, 1 << 17);
  EXPECT_EQ(y, -(1 << 17));
  EXPECT_FALSE(carry_along_lines(8, 6, {0, 0}, {1, 2}, &x, &y));
  EXPECT_FALSE(carry_along_lines(8, 6, {1, 2}, {0, 0}, &x, &y));
}

TEST(CodecEpipolar, LinesRoundTripThroughTheRangeCoderAndLargeOnesAreRefused) {
  const std::vector<EpipolarLines> values = {{0, 0, 0}, {1, -1, 0}, {-4096, 4096, 17}, {3, 0, -2}};
  std::vector<uint8_t> bytes;
  RangeEncoder encoder(&bytes);
  for (const EpipolarLines& lines : values) bframe::encode_epipolar_lines(encoder, lines);
  encode_exp_golomb_bypass(encoder, 2 * 4097);  // a = 4097: beyond the limit
  encoder.finish();
  RangeDecoder decoder(bytes);
  for (const EpipolarLines& expected : values) {
    EpipolarLines lines;
    ASSERT_TRUE(bframe::decode_epipolar_lines(decoder, &lines));
    EXPECT_EQ(lines, expected);
  }
  EpipolarLines refused;
  EXPECT_FALSE(bframe::decode_epipolar_lines(decoder, &refused));
}

}  // namespace
}  // namespace svc::codec
