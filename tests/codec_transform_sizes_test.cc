// SPDX-License-Identifier: BSD-2-Clause
// Transform sizes 4x4, 16x16 and the rectangular ones: the integer inverses against their
// definitions and the exact transform, their scans and level coding, and intra frames that
// choose them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "codec/common/coefficient_contexts.h"
#include "codec/common/dct.h"
#include "codec/common/intra_frame.h"
#include "codec/common/intra_prediction.h"
#include "codec/common/quant.h"
#include "codec/decoder/coefficient_reader.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/decoder/range_decoder.h"
#include "codec/encoder/coefficient_writer.h"
#include "codec/encoder/forward_transform.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/range_encoder.h"
#include "support/random_coefficients.h"

namespace svc::codec {
namespace {

constexpr TransformSize kNewSizes[] = {TransformSize::k4x4,  TransformSize::k16x16, TransformSize::k16x8,
                                       TransformSize::k8x16, TransformSize::k16x4,  TransformSize::k4x16,
                                       TransformSize::k8x4,  TransformSize::k4x8};

using testing::random_coefficients;

// Encodes `image` as an intra frame, parses it into *parsed and expects the decoder to
// reproduce the encoder's reconstruction exactly.
void encode_and_decode_exactly(const ImageYCbCr420& image, const CodingParams& params, CoefficientFrame* parsed) {
  ImageYCbCr420 reconstruction, decoded;
  const auto bytes = encode_intra_frame(image, params, &reconstruction);
  ASSERT_TRUE(parse_intra_frame(bytes, image.width, image.height, parsed).ok());
  reconstruct_intra_frame(*parsed, &decoded);
  EXPECT_TRUE(decoded.y == reconstruction.y && decoded.cb == reconstruction.cb && decoded.cr == reconstruction.cr);
}

TEST(TransformSizes, IntegerInversesMatchTheirMatrixProductsBitExactly) {
  std::mt19937 rng(11);
  for (TransformSize size : kNewSizes) {
    const int area = transform_area(size);
    for (int n = 0; n < 500; ++n) {
      const auto coefficients = random_coefficients(rng, area);
      std::vector<int16_t> fast(static_cast<size_t>(area)), reference(static_cast<size_t>(area));
      inverse_transform(size, coefficients.data(), fast.data());
      inverse_transform_integer_reference(size, coefficients.data(), reference.data());
      ASSERT_EQ(fast, reference) << "size " << transform_width(size) << ", block " << n;
    }
  }
}

// Residual-like blocks through the float forward transform, rounded to integers: the
// integer inverse stays within one of the exact inverse and of the samples.
TEST(TransformSizes, IntegerInversesStayWithinOneOfTheExactInverse) {
  std::mt19937 rng(12);
  for (TransformSize size : kNewSizes) {
    const int area = transform_area(size);
    int peak = 0;
    double squared = 0;
    for (int n = 0; n < 2000; ++n) {
      std::vector<float> samples(static_cast<size_t>(area)), coefficients(static_cast<size_t>(area));
      const int range = n % 2 ? 255 : 20;
      for (float& s : samples) s = static_cast<float>(static_cast<int>(rng() % (2 * range + 1)) - range);
      forward_transform(size, samples.data(), coefficients.data());
      std::vector<int16_t> rounded(static_cast<size_t>(area)), out(static_cast<size_t>(area));
      std::vector<double> exact_in(static_cast<size_t>(area)), exact(static_cast<size_t>(area));
      for (int i = 0; i < area; ++i) {
        const double c =
            std::clamp(std::round(static_cast<double>(coefficients[static_cast<size_t>(i)])), -2048.0, 2047.0);
        rounded[static_cast<size_t>(i)] = static_cast<int16_t>(c);
        exact_in[static_cast<size_t>(i)] = c;
      }
      inverse_transform(size, rounded.data(), out.data());
      inverse_transform_reference(size, exact_in.data(), exact.data());
      for (int i = 0; i < area; ++i) {
        const double error = out[static_cast<size_t>(i)] - exact[static_cast<size_t>(i)];
        peak = std::max(peak, static_cast<int>(std::ceil(std::fabs(error) - 0.5)));
        squared += error * error;
      }
    }
    EXPECT_LE(peak, 1) << "size " << transform_width(size);
    EXPECT_LT(squared / (2000.0 * area), 0.25) << "size " << transform_width(size);
  }
}

TEST(TransformSizes, DcKeepsTheScaleOfEachSize) {
  // A flat block of 10: 4x4 DC = 4 x 10 (orthonormal), 16x16 DC = 8 x 10 (half of 16 x 10),
  // 16x8 and 8x16 DC = 8 x 10 (sqrt(128) x 10 / sqrt(2)), 16x4 and 4x16 DC = 8 x 10
  // (orthonormal), 8x4 and 4x8 DC = 8 x 10 (sqrt(32) x 10 x sqrt(2)).
  for (TransformSize size : kNewSizes) {
    const int area = transform_area(size);
    std::vector<float> samples(static_cast<size_t>(area), 10.0f), coefficients(static_cast<size_t>(area));
    forward_transform(size, samples.data(), coefficients.data());
    EXPECT_NEAR(coefficients[0], size == TransformSize::k4x4 ? 40.0 : 80.0, 1e-3);
    std::vector<int16_t> dc(static_cast<size_t>(area), 0), out(static_cast<size_t>(area));
    dc[0] = static_cast<int16_t>(std::lround(coefficients[0]));
    inverse_transform(size, dc.data(), out.data());
    EXPECT_TRUE(std::all_of(out.begin(), out.end(), [](int16_t v) { return v == 10; }));
  }
  EXPECT_EQ(residual_step(TransformSize::k4x4, 100), residual_step(TransformSize::k8x8, 100));
  EXPECT_EQ(residual_step(TransformSize::k16x16, 100), (residual_step(TransformSize::k8x8, 100) + 1) / 2);
  EXPECT_EQ(residual_step(TransformSize::k16x16, 0), 128);  // never finer than 128 / 256
  EXPECT_EQ(residual_step(TransformSize::k16x8, 100), (residual_step(TransformSize::k8x8, 100) * 181 + 128) >> 8);
  EXPECT_EQ(residual_step(TransformSize::k8x16, 100), residual_step(TransformSize::k16x8, 100));
  EXPECT_EQ(residual_step(TransformSize::k16x4, 100), residual_step(TransformSize::k8x8, 100));
  EXPECT_EQ(residual_step(TransformSize::k4x16, 100), residual_step(TransformSize::k8x8, 100));
  EXPECT_EQ(residual_step(TransformSize::k8x4, 100), (residual_step(TransformSize::k8x8, 100) * 362 + 128) >> 8);
  EXPECT_EQ(residual_step(TransformSize::k4x8, 100), residual_step(TransformSize::k8x4, 100));
}

TEST(TransformSizes, ScansVisitEveryPositionByAntiDiagonal) {
  for (int s = 0; s < kTransformSizes; ++s) {
    const TransformSize size = static_cast<TransformSize>(s);
    const ScanOrder& order = scan_order(size);
    ASSERT_EQ(order.width, transform_width(size));
    ASSERT_EQ(order.height, transform_height(size));
    ASSERT_EQ(order.count, transform_area(size));
    std::set<int> seen;
    int previous_diagonal = 0;
    for (int i = 0; i < order.count; ++i) {
      const int position = order.scan[i], diagonal = position / order.width + position % order.width;
      EXPECT_GE(diagonal, previous_diagonal);
      previous_diagonal = diagonal;
      seen.insert(position);
    }
    EXPECT_EQ(static_cast<int>(seen.size()), order.count);
  }
}

TEST(TransformSizes, LevelsOfEverySizeRoundTripThroughTheBlockCoder) {
  std::mt19937 rng(13);
  std::vector<uint8_t> bytes;
  RangeEncoder encoder(&bytes);
  BlockContextSet encoding;
  std::vector<std::pair<TransformSize, std::vector<int16_t>>> blocks;
  for (int n = 0; n < 300; ++n) {
    const TransformSize size = static_cast<TransformSize>(n % kTransformSizes);
    std::vector<int16_t> levels(static_cast<size_t>(transform_area(size)), 0);
    for (auto& level : levels) {
      if (rng() % 5 == 0) level = static_cast<int16_t>(static_cast<int>(rng() % 41) - 20);
    }
    if (n % 7 == 0) levels.back() = kMaxLevel;  // the last scan position of 4x4 and 16x16 too
    encode_block_levels(encoder, encoding, levels.data(), n % 3, size);
    blocks.emplace_back(size, levels);
  }
  encoder.finish();
  RangeDecoder decoder(bytes);
  BlockContextSet decoding;
  for (size_t n = 0; n < blocks.size(); ++n) {
    const auto& [size, levels] = blocks[n];
    BlockLevel out[kMaxTransformArea];
    int count = 0;
    ASSERT_TRUE(decode_block_levels(decoder, decoding, static_cast<int>(n % 3), out, &count, size));
    std::vector<int16_t> decoded(levels.size(), 0);
    for (int i = 0; i < count; ++i) decoded[out[i].position] = out[i].level;
    ASSERT_EQ(decoded, levels) << "block " << n;
  }
}

// Left half smooth (a gentle gradient), right half 4x4 tiles of alternating brightness
// over it: the encoder codes the smooth macroblocks as 16x16 and splits some tiled 8x8
// blocks into 4x4; the decoder follows. Without the tool every macroblock is four 8x8
// blocks.
TEST(TransformSizes, IntraFramesChooseEverySizeAndDecodeExactly) {
  ImageYCbCr420 image;
  image.width = 96;
  image.height = 64;
  std::mt19937 rng(14);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const double detail = x < 48 ? 0.0 : 80.0 * (((x % 8) < 4) != ((y % 8) < 4)) + (rng() % 11);
      image.y.push_back(static_cast<uint8_t>(std::clamp(60 + x + 0.5 * y + detail, 0.0, 255.0)));
    }
  }
  image.cb.assign(48 * 32, 120);
  image.cr.assign(48 * 32, 140);
  for (bool sizes : {true, false}) {
    CodingParams params;
    params.qindex = 90;
    params.transform_sizes = sizes;
    params.transform_types = false;  // with DST types the detailed 8x8 blocks rarely split
    CoefficientFrame parsed;
    ASSERT_NO_FATAL_FAILURE(encode_and_decode_exactly(image, params, &parsed));
    const auto whole = std::count(parsed.luma_partitions.begin(), parsed.luma_partitions.end(), 0);
    const auto with_4x4 = std::count_if(parsed.luma_partitions.begin(), parsed.luma_partitions.end(),
                                        [](uint8_t p) { return (p & 0x1E) != 0; });
    if (sizes) {
      EXPECT_GT(whole, 0);
      EXPECT_GT(with_4x4, 0);
    } else {
      EXPECT_TRUE(std::all_of(parsed.luma_partitions.begin(), parsed.luma_partitions.end(),
                              [](uint8_t p) { return p == 1; }));
    }
  }
}

// Rectangular prediction (docs/codec.md 5.2): a flat edge predicts flat in every mode;
// the diagonals copy the edge (mode 2 the left column from row x + y + 1, mode 34 the
// above row from column x + y + 1, both smoothed: on a linear edge smoothing changes
// nothing); pure horizontal copies the left column beyond the first row.
TEST(TransformSizes, RectangularPredictionFollowsTheEdge) {
  for (TransformSize size : {TransformSize::k16x8, TransformSize::k8x16, TransformSize::k16x4, TransformSize::k4x16,
                             TransformSize::k8x4, TransformSize::k4x8}) {
    const int w = transform_width(size), h = transform_height(size), corner = w + h;
    uint8_t edge[2 * 24 + 1], out[128];
    std::fill_n(edge, 2 * corner + 1, uint8_t{90});
    for (int mode = 0; mode < kIntraModes; ++mode) {
      intra_predictor(size)(edge, mode, out);
      ASSERT_TRUE(std::all_of(out, out + w * h, [](uint8_t v) { return v == 90; })) << w << "x" << h << " " << mode;
    }
    for (int i = 0; i < corner; ++i) {
      edge[corner - 1 - i] = static_cast<uint8_t>(50 + 3 * i);   // left of row i
      edge[corner + 1 + i] = static_cast<uint8_t>(100 + 2 * i);  // above column i
    }
    edge[corner] = 47;
    intra_predictor(size)(edge, 2, out);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) ASSERT_EQ(out[w * y + x], 50 + 3 * (x + y + 1)) << w << "x" << h;
    }
    intra_predictor(size)(edge, 34, out);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) ASSERT_EQ(out[w * y + x], 100 + 2 * (x + y + 1)) << w << "x" << h;
    }
    intra_predictor(size)(edge, kHorizontalMode, out);
    for (int y = 1; y < h; ++y) {
      for (int x = 0; x < w; ++x) ASSERT_EQ(out[w * y + x], 50 + 3 * y);
    }
  }
}

// A 64x64 picture whose luma is luma(along, across), along the rows (across the columns
// when transposed), flat chroma, coded at qindex 120 and decoded exactly; returns the
// number of macroblock partitions `partition` (or its transposed counterpart) matches.
template <class Luma, class Matches>
int partitions_chosen(bool transposed, Luma luma, Matches matches) {
  ImageYCbCr420 image;
  image.width = image.height = 64;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x)
      image.y.push_back(static_cast<uint8_t>(transposed ? luma(y, x) : luma(x, y)));
  }
  image.cb.assign(32 * 32, 128);
  image.cr.assign(32 * 32, 128);
  CodingParams params;
  params.qindex = 120;
  CoefficientFrame parsed;
  encode_and_decode_exactly(image, params, &parsed);
  return static_cast<int>(std::count_if(parsed.luma_partitions.begin(), parsed.luma_partitions.end(), matches));
}

// Macroblocks whose top and bottom halves hold different gradients along their rows: the
// encoder codes some as two 16x8 blocks, and the transposed picture's as two 8x16 blocks;
// the decoder follows.
TEST(TransformSizes, IntraFramesChooseHalvesAndDecodeExactly) {
  for (bool transposed : {false, true}) {
    const uint16_t halves = transposed ? 32 | 64 : 32;  // 8x16 or 16x8 halves
    const int chosen = partitions_chosen(
        transposed,
        [](int along, int across) { return (across % 16) < 8 ? 40 + 3 * (along % 16) : 200 - 5 * (along % 16); },
        [&](uint16_t partition) { return partition == halves; });
    EXPECT_GT(chosen, 0) << (transposed ? "8x16" : "16x8");
  }
}

// The same with four different gradients down each macroblock, one per 4 rows: some
// macroblocks are coded as four 16x4 strips, and the transposed picture's as four 4x16.
TEST(TransformSizes, IntraFramesChooseStripsAndDecodeExactly) {
  for (bool transposed : {false, true}) {
    const uint16_t strips = transposed ? 32 | 64 | 128 : 32 | 128;  // 4x16 or 16x4 strips
    const int chosen = partitions_chosen(
        transposed,
        [](int along, int across) {
          constexpr int kBase[4] = {40, 200, 70, 170}, kSlope[4] = {3, -5, 4, -3};
          const int strip = (across % 16) / 4;
          return kBase[strip] + kSlope[strip] * (along % 16);
        },
        [&](uint16_t partition) { return partition == strips; });
    EXPECT_GT(chosen, 0) << (transposed ? "4x16" : "16x4");
  }
}

// Each 8x8 block two different gradients, one per 4 rows, and its right neighbour two
// others: some 8x8 blocks are coded as two 8x4 blocks, and the transposed picture's as
// two 4x8 blocks (partition bits 8 + i, with 12 + i).
TEST(TransformSizes, IntraFramesChooseHalvesOf8x8BlocksAndDecodeExactly) {
  for (bool transposed : {false, true}) {
    const int chosen = partitions_chosen(
        transposed,
        [](int along, int across) {
          constexpr int kBase[4] = {40, 200, 170, 60}, kSlope[4] = {6, -9, -7, 8};
          const int region = 2 * ((along / 8) % 2) + (across % 8) / 4;
          return kBase[region] + kSlope[region] * (along % 8);
        },
        [&](uint16_t partition) {
          bool any = false;
          for (int i = 0; i < 4; ++i) {
            const bool vertical = (partition & (4096 << i)) != 0;
            any = any || ((partition & 1) != 0 && (partition & (256 << i)) != 0 && vertical == transposed);
          }
          return any;
        });
    EXPECT_GT(chosen, 0) << (transposed ? "4x8" : "8x4");
  }
}

}  // namespace
}  // namespace svc::codec
