// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "codec/common/intra_frame.h"
#include "codec/common/intra_macroblock.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/intra_search.h"
#include "codec/encoder/intra_syntax_writer.h"

namespace svc::codec {
namespace {

// A deterministic photograph-like test image: lit gradients, soft shapes with hard
// edges, periodic texture of several frequencies and mild noise, in all three planes.
ImageYCbCr420 synthetic_image(int width, int height, uint32_t seed = 1) {
  std::mt19937 rng(seed);
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  image.y.resize(static_cast<size_t>(width) * height);
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  image.cb.resize(static_cast<size_t>(cw) * ch);
  image.cr.resize(image.cb.size());
  auto clamp8 = [](double v) { return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 255.0))); };
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double v = 60 + 100.0 * x / std::max(1, width) + 40.0 * y / std::max(1, height);
      const double dx = x - 0.35 * width, dy = y - 0.4 * height;
      if (dx * dx + dy * dy < 0.06 * width * width) v = 200 - 0.3 * dy;  // a lit disc
      if (x > 0.6 * width && y > 0.55 * height) {                        // a textured box
        v = 90 + 25 * std::sin(x * 0.7) * std::cos(y * 0.45) + 10 * std::sin((x + y) * 0.19);
      }
      if (y < 0.2 * height) v += 12 * std::sin(x * 0.11 + y * 0.05);  // sky-like waves
      v += static_cast<double>(rng() % 9) - 4;                        // sensor noise
      image.y[static_cast<size_t>(y) * width + x] = clamp8(v);
    }
  }
  for (int y = 0; y < ch; ++y) {
    for (int x = 0; x < cw; ++x) {
      const size_t i = static_cast<size_t>(y) * cw + x;
      image.cb[i] = clamp8(110 + 30.0 * x / cw + 6 * std::sin(y * 0.3) + static_cast<double>(rng() % 3));
      image.cr[i] = clamp8(150 - 25.0 * y / ch + ((x > cw / 2) ? 15 : 0) + static_cast<double>(rng() % 3));
    }
  }
  return image;
}

double psnr(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double squared = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = static_cast<double>(a[i]) - static_cast<double>(b[i]);
    squared += d * d;
  }
  if (squared == 0) return 99.0;
  return 10 * std::log10(255.0 * 255.0 * a.size() / squared);
}

void expect_same_image(const ImageYCbCr420& a, const ImageYCbCr420& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_TRUE(a.y == b.y);
  EXPECT_TRUE(a.cb == b.cb);
  EXPECT_TRUE(a.cr == b.cr);
}

// A kStride x kStride plane of grey 128 whose macroblock (1, 1) takes value(x, y) at
// (16 + x, 16 + y).
constexpr int kStride = 32;
template <class Value>
std::vector<uint8_t> plane_around_macroblock(Value value) {
  std::vector<uint8_t> plane(kStride * kStride, 128);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x)
      plane[static_cast<size_t>(16 + y) * kStride + 16 + x] = static_cast<uint8_t>(value(x, y));
  }
  return plane;
}

// A B-face's intra search gets the cost of its best inter option as a budget (only a
// cheaper macroblock can be chosen): once the split's running cost reaches it, only the
// 16x16 block is searched further.
TEST(IntraMacroblockSearch, BudgetStopsTheSplitAndLeavesTheWholeBlock) {
  using namespace intra;
  // Macroblock (1, 1) of a 32x32 plane: four 8x8 quadrants of unlike texture (vertical
  // and horizontal stripes, a diagonal ramp, flat), which split blocks predict best.
  const std::vector<uint8_t> plane = plane_around_macroblock([](int x, int y) {
    const int quadrant = (y / 8) * 2 + x / 8;
    return quadrant == 0   ? (x % 4 < 2 ? 40 : 210)
           : quadrant == 1 ? (y % 4 < 2 ? 60 : 190)
           : quadrant == 2 ? 30 + 12 * (x + y)
                           : 100;
  });
  CodingParams params;
  params.qindex = 60;
  params.coarse_mode_search = true;
  MacroblockEncoder search(params, params.qindex, 20.0f);
  struct Searched {
    float cost = 0;
    MacroblockChoice choice;
    std::vector<uint8_t> recon;
  };
  auto run = [&](float budget) {
    PlaneContexts contexts;
    PlaneState state(kStride, kStride);
    Searched out;
    out.recon.assign(plane.size(), 128);
    out.cost =
        search.choose_luma(contexts, state, plane.data(), out.recon.data(), kStride, 1, 1, &out.choice, budget);
    return out;
  };
  const Searched full = run(std::numeric_limits<float>::infinity());
  ASSERT_NE(full.choice.partition & kSplit16x16, 0) << "the test needs a macroblock whose split wins";

  // A budget above every partition's cost changes nothing.
  const Searched roomy = run(1e30f);
  EXPECT_EQ(roomy.cost, full.cost);
  EXPECT_EQ(roomy.choice.partition, full.choice.partition);
  EXPECT_EQ(roomy.recon, full.recon);

  // A budget the first 8x8 block already exceeds: the 16x16 block, reconstructed in place,
  // costing at least what the full search found.
  const Searched tight = run(1.0f);
  EXPECT_EQ(tight.choice.partition, 0);
  EXPECT_GE(tight.cost, full.cost);
  EXPECT_LT(tight.cost, std::numeric_limits<float>::infinity());
  EXPECT_NE(tight.recon, full.recon);
  int changed = 0;
  for (int y = 16; y < 32; ++y) {
    for (int x = 16; x < 32; ++x) changed += tight.recon[static_cast<size_t>(y) * kStride + x] != 128;
  }
  EXPECT_GT(changed, 128);
}

// Without small blocks (B-faces at the highest encoder speed) no 8x8 block of the
// macroblock is split into 4x4, 8x4 or 4x8 blocks, where the full search splits one.
TEST(IntraMacroblockSearch, WithoutSmallBlocksNoEightByEightIsSplit) {
  using namespace intra;
  // Macroblock (1, 1) of a 32x32 plane: each 8x8 quadrant holds four flat 4x4 squares
  // of unlike values, which 4x4 blocks predict best.
  const std::vector<uint8_t> plane =
      plane_around_macroblock([](int x, int y) { return 20 + (((y / 4) * 4 + x / 4) * 97) % 220; });
  constexpr LumaPartition kSmallBlocks =
      static_cast<LumaPartition>(split_8x8_bit(0) | split_8x8_bit(1) | split_8x8_bit(2) | split_8x8_bit(3) |
                                 halves_8x8_bit(0) | halves_8x8_bit(1) | halves_8x8_bit(2) | halves_8x8_bit(3));
  auto run = [&](bool small_blocks) {
    CodingParams params;
    params.qindex = 40;
    params.coarse_mode_search = true;
    params.small_blocks = small_blocks;
    MacroblockEncoder search(params, params.qindex, 20.0f);
    PlaneContexts contexts;
    PlaneState state(kStride, kStride);
    std::vector<uint8_t> recon(plane.size(), 128);
    MacroblockChoice choice;
    const float cost = search.choose_luma(contexts, state, plane.data(), recon.data(), kStride, 1, 1, &choice);
    return std::pair{cost, choice.partition};
  };
  const auto [full_cost, full_partition] = run(true);
  ASSERT_NE(full_partition & kSmallBlocks, 0) << "the test needs a macroblock whose 8x8 blocks split";
  const auto [restricted_cost, restricted_partition] = run(false);
  EXPECT_EQ(restricted_partition & kSmallBlocks, 0);
  EXPECT_GT(restricted_cost, full_cost);
}

// The first stage narrows the search: with one rectangular and one smaller partition
// searched, the choice costs at least the full search's and is one of the partitions the
// first stage may keep; searched again in its own partition, a choice keeps it.
TEST(IntraMacroblockSearch, NarrowedAndKeptPartitionSearches) {
  using namespace intra;
  const std::vector<uint8_t> plane = plane_around_macroblock([](int x, int y) {
    const int quadrant = (y / 8) * 2 + x / 8;
    return quadrant == 0   ? 20 + (((y / 4) * 4 + x / 4) * 97) % 220
           : quadrant == 1 ? (y % 4 < 2 ? 60 : 190)
           : quadrant == 2 ? 30 + 12 * (x + y)
                           : 100 + 9 * (y % 8);
  });
  struct Searched {
    float cost = 0;
    MacroblockChoice choice;
    std::vector<uint8_t> recon;
  };
  auto run = [&](int rectangular, int small, const LumaPartition* partition) {
    CodingParams params;
    params.qindex = 50;
    params.coarse_mode_search = true;
    params.rectangular_trials = rectangular;
    params.small_trials = small;
    MacroblockEncoder search(params, params.qindex, 20.0f);
    PlaneContexts contexts;
    PlaneState state(kStride, kStride);
    Searched out;
    out.recon.assign(plane.size(), 128);
    out.cost = search.choose_luma(contexts, state, plane.data(), out.recon.data(), kStride, 1, 1, &out.choice,
                                  std::numeric_limits<float>::infinity(), partition);
    return out;
  };
  const Searched full = run(4, 3, nullptr);
  for (const auto& [rectangular, small] : {std::pair{1, 1}, {0, 0}, {2, 3}, {4, 1}}) {
    SCOPED_TRACE(std::to_string(rectangular) + " rectangular, " + std::to_string(small) + " small");
    const Searched narrowed = run(rectangular, small, nullptr);
    EXPECT_GE(narrowed.cost, full.cost);
    if (rectangular == 0) EXPECT_EQ(narrowed.choice.partition & (kHalves16x16 | kStrips), 0);
    if (small == 0) {
      for (int i = 0; i < 4; ++i) EXPECT_EQ(narrowed.choice.partition & (split_8x8_bit(i) | halves_8x8_bit(i)), 0);
    }
  }
  for (const LumaPartition partition :
       {full.choice.partition, LumaPartition{0}, LumaPartition{kHalves16x16 | kStrips},
        LumaPartition{kSplit16x16 | split_8x8_bit(0)}}) {
    SCOPED_TRACE("partition " + std::to_string(partition));
    Searched kept;
    kept.choice = full.choice;  // the choice searched again
    CodingParams params;
    params.qindex = 50;
    params.coarse_mode_search = true;
    MacroblockEncoder search(params, params.qindex, 20.0f);
    PlaneContexts contexts;
    PlaneState state(kStride, kStride);
    kept.recon.assign(plane.size(), 128);
    kept.cost = search.choose_luma(contexts, state, plane.data(), kept.recon.data(), kStride, 1, 1, &kept.choice,
                                   std::numeric_limits<float>::infinity(), &partition);
    // A split 8x8 block may come back whole where its levels vanish; nothing else moves.
    const LumaPartition small_bits = 0xFF1E;  // every 8x8 block's split, halves and vertical bits
    EXPECT_EQ(kept.choice.partition & ~small_bits, partition & ~small_bits);
    EXPECT_EQ(kept.choice.partition & small_bits & ~partition, 0);
    EXPECT_GE(kept.cost, full.cost);
  }
}

TEST(CodecFrame, DecodeEqualsEncoderReconstructionForManySizesAndScales) {
  for (auto [width, height] : {std::pair{256, 256}, {17, 9}, {1, 1}, {250, 130}, {16, 16}, {33, 70}}) {
    const ImageYCbCr420 source = synthetic_image(width, height, static_cast<uint32_t>(width + height));
    for (int qs : {0, 32, 83, 128, 170, 220, 255}) {
      SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) + " qindex " + std::to_string(qs));
      ImageYCbCr420 reconstruction, decoded;
      const std::vector<uint8_t> bytes = encode_intra_frame(source, {qs}, &reconstruction);
      ASSERT_GE(bytes.size(), static_cast<size_t>(kFrameHeaderBytes));
      EXPECT_EQ(bytes[0], kIntraSyntaxVersion);  // type bit 0: intra
      EXPECT_EQ(bytes[kQIndexByte], qs);
      const Status status = decode_intra_frame(bytes, width, height, &decoded);
      ASSERT_TRUE(status.ok()) << status.to_string();
      expect_same_image(decoded, reconstruction);
      ASSERT_EQ(decoded.y.size(), source.y.size());
      ASSERT_EQ(decoded.cb.size(), source.cb.size());
      if (qs <= 83) EXPECT_GT(psnr(source.y, decoded.y), 40.0);
      // Encoding is deterministic.
      EXPECT_EQ(encode_intra_frame(source, {qs}, nullptr), bytes);
    }
  }
}

// Every search setting writes what the decoder reads: without rate-distortion
// quantization the block's levels come as quantized, and without the mode search's
// rate-distortion step (or without transform types) a block is kept coded as chosen,
// so a wrong count of levels in any block size would put encoder and decoder out of step.
TEST(CodecFrame, DecodeEqualsEncoderReconstructionWithEverySearchSetting) {
  const ImageYCbCr420 source = synthetic_image(96, 80, 5);
  for (int setting = 0; setting < 16; ++setting) {
    CodingParams params{60};
    params.rdoq = (setting & 1) != 0;
    params.rd_intra_search = (setting & 2) != 0;
    params.transform_types = (setting & 4) != 0;
    // The first stage's narrowed partition search.
    params.rectangular_trials = (setting & 8) != 0 ? 1 : 4;
    params.small_trials = (setting & 8) != 0 ? 1 : 3;
    SCOPED_TRACE("setting " + std::to_string(setting));
    for (int qs : {40, 100, 160}) {
      params.qindex = qs;
      ImageYCbCr420 reconstruction, decoded;
      const std::vector<uint8_t> bytes = encode_intra_frame(source, params, &reconstruction);
      const Status status = decode_intra_frame(bytes, 96, 80, &decoded);
      ASSERT_TRUE(status.ok()) << "qindex " << qs << ": " << status.to_string();
      expect_same_image(decoded, reconstruction);
      EXPECT_EQ(encode_intra_frame(source, params, nullptr), bytes);
    }
  }
}

TEST(CodecFrame, QualityRisesAndSizeGrowsAsQIndexFalls) {
  const ImageYCbCr420 source = synthetic_image(256, 256);
  double previous_psnr = 0;
  size_t previous_bytes = 0;
  for (int qs : {255, 224, 192, 160, 128, 96, 64, 32, 0}) {
    ImageYCbCr420 decoded;
    const std::vector<uint8_t> bytes = encode_intra_frame(source, {qs}, &decoded);
    CoefficientFrame coefficients;
    ASSERT_TRUE(parse_intra_frame(bytes, 256, 256, &coefficients).ok());
    const double y_psnr = psnr(source.y, decoded.y);
    const double cb_psnr = psnr(source.cb, decoded.cb);
    std::printf(
        "[ synthetic 256x256 ] qindex %3d: %6zu bytes, %.3f bit/pixel, PSNR-Y %.2f dB, "
        "PSNR-Cb %.2f dB, coefficient cache %zu bytes (%.3f x RGB)\n",
        qs, bytes.size(), bytes.size() * 8.0 / (256 * 256), y_psnr, cb_psnr, coefficients.memory_bytes(),
        coefficients.memory_bytes() / (3.0 * 256 * 256));
    // Index 0 (a step of half a coefficient unit, PSNR-Y near 60 dB) is finer than the
    // 8-bit samples it rebuilds: it may buy nothing over 32.
    EXPECT_GT(y_psnr, previous_psnr + (qs > 0 ? 0.3 : -0.5)) << "qindex " << qs;
    EXPECT_GT(bytes.size(), previous_bytes) << "qindex " << qs;
    previous_psnr = y_psnr;
    previous_bytes = bytes.size();
    if (qs == 128) {
      EXPECT_GT(y_psnr, 36.0);
      // The semi-decoded form is far smaller than the RGB pixels it stands for.
      EXPECT_LT(coefficients.memory_bytes(), static_cast<size_t>(0.25 * 3 * 256 * 256));
    }
  }
  EXPECT_GT(previous_psnr, 48.0);  // qindex 0
}

TEST(CodecFrame, FlatImageCodesToAFewBytesAndExactly) {
  ImageYCbCr420 flat;
  flat.width = 100;
  flat.height = 60;
  flat.y.assign(100 * 60, 77);
  flat.cb.assign(50 * 30, 140);
  flat.cr.assign(50 * 30, 99);
  ImageYCbCr420 decoded;
  const std::vector<uint8_t> bytes = encode_intra_frame(flat, {128}, nullptr);
  EXPECT_LT(bytes.size(), 40u);
  ASSERT_TRUE(decode_intra_frame(bytes, 100, 60, &decoded).ok());
  expect_same_image(decoded, flat);
}

TEST(CodecFrame, ParsedCoefficientsReconstructTheSameImage) {
  const ImageYCbCr420 source = synthetic_image(64, 48);
  ImageYCbCr420 reconstruction, from_coefficients;
  const std::vector<uint8_t> bytes = encode_intra_frame(source, {106}, &reconstruction);
  CoefficientFrame coefficients;
  ASSERT_TRUE(parse_intra_frame(bytes, 64, 48, &coefficients).ok());
  EXPECT_EQ(coefficients.width, 64);
  EXPECT_EQ(coefficients.qindex, 106);
  // One partition per macroblock; blocks as the partitions count them (a 16x16 block
  // is one, halves two, strips four, an 8x8 split into 4x4 four or into halves two)
  // plus the 8x8 chroma blocks.
  ASSERT_EQ(coefficients.luma_partitions.size(), 12u);
  size_t blocks = 2 * 12;
  for (uint16_t partition : coefficients.luma_partitions) {
    if ((partition & intra::kSplit16x16) != 0) {
      blocks += 4 + 3 * static_cast<size_t>(std::popcount(unsigned{partition} >> 1 & 15u)) +
                static_cast<size_t>(std::popcount(unsigned{partition} >> 8 & 15u));
    } else {
      blocks += (partition & intra::kHalves16x16) == 0 ? 1 : (partition & intra::kStrips) != 0 ? 4 : 2;
    }
  }
  EXPECT_EQ(coefficients.block_counts.size(), blocks);
  reconstruct_intra_frame(coefficients, &from_coefficients);
  expect_same_image(from_coefficients, reconstruction);
}

// The parse's unpacked levels give the packed levels' pixels; levels that do not match
// the frame are ignored, not read past.
TEST(CodecFrame, DecodedLevelsReconstructLikeThePackedOnes) {
  const ImageYCbCr420 source = synthetic_image(80, 64);
  ImageYCbCr420 reconstruction, from_packed, from_decoded, from_mismatched;
  const std::vector<uint8_t> bytes = encode_intra_frame(source, {60}, &reconstruction);
  CoefficientFrame coefficients;
  DecodedLevels decoded;
  ASSERT_TRUE(parse_intra_frame(bytes, 80, 64, &coefficients, &decoded).ok());
  size_t levels = 0, blocks_with_levels = 0;
  for (uint16_t count : coefficients.block_counts) {
    levels += count;
    blocks_with_levels += count > 0;
  }
  ASSERT_GT(levels, 100u);
  EXPECT_EQ(decoded.levels.size(), levels);
  EXPECT_EQ(decoded.types.size(), blocks_with_levels);
  reconstruct_intra_frame(coefficients, &from_packed);
  reconstruct_intra_frame(coefficients, &from_decoded, &decoded);
  expect_same_image(from_decoded, reconstruction);
  expect_same_image(from_packed, reconstruction);

  // They are what is read: altered levels of the right count change the pixels.
  DecodedLevels altered = decoded;
  for (BlockLevel& level : altered.levels) level.level = static_cast<int16_t>(-level.level);
  ImageYCbCr420 from_altered;
  reconstruct_intra_frame(coefficients, &from_altered, &altered);
  EXPECT_NE(from_altered.y, reconstruction.y);

  DecodedLevels mismatched = decoded;
  mismatched.levels.pop_back();
  for (BlockLevel& level : mismatched.levels) level.level = static_cast<int16_t>(level.level * 3);
  reconstruct_intra_frame(coefficients, &from_mismatched, &mismatched);
  expect_same_image(from_mismatched, reconstruction);
}
TEST(CodecFrame, PackedLevelsRoundTripAtEveryRunAndMagnitude) {
  std::mt19937 rng(5);
  for (TransformSize size : {TransformSize::k4x4, TransformSize::k8x8, TransformSize::k16x16}) {
    const ScanOrder& order = scan_order(size);
    for (int trial = 0; trial < 200; ++trial) {
      // Random non-zero levels at increasing scan indices, with the extremes: a level at
      // the last scan index only (the longest run) and magnitudes 1 and 4095.
      std::vector<BlockLevel> block;
      for (int scan = 0; scan < order.count; ++scan) {
        const bool last_only = trial == 0;
        if (last_only ? scan != order.count - 1 : rng() % 3 != 0) continue;
        const int magnitude = trial == 1 ? 4095 : rng() % 4 == 0 ? 1 + static_cast<int>(rng() % 4095) : 1;
        block.push_back({order.scan[scan], static_cast<int16_t>(rng() % 2 ? -magnitude : magnitude)});
      }
      CoefficientFrame frame;
      const auto type = static_cast<TransformType>(trial % kTransformTypes);
      frame.append_levels(block.data(), static_cast<int>(block.size()), size, type);
      frame.append_levels(block.data(), 1, size);  // a second block follows on the next byte
      size_t offset = 0;
      int positions[kMaxTransformArea], values[kMaxTransformArea];
      TransformType read_type = TransformType::kDctDct;
      ASSERT_EQ(frame.read_levels(&offset, static_cast<int>(block.size()), size, positions, values, &read_type),
                static_cast<int>(block.size()));
      EXPECT_EQ(read_type, type);
      for (size_t i = 0; i < block.size(); ++i) {
        EXPECT_EQ(positions[i], block[i].position);
        EXPECT_EQ(values[i], block[i].level);
      }
      ASSERT_EQ(frame.read_levels(&offset, 1, size, positions, values, &read_type), 1);
      EXPECT_EQ(read_type, TransformType::kDctDct);
      EXPECT_EQ(positions[0], block[0].position);
      EXPECT_EQ(offset, frame.levels.size());
      // Past the end nothing more is read, whatever count is asked for.
      EXPECT_EQ(frame.read_levels(&offset, 5, size, positions, values, &read_type), 0);
    }
  }
  // The commonest level, a 1 right after the previous one, takes 3 bits (after the
  // transform type's 2).
  CoefficientFrame ones;
  std::vector<BlockLevel> dense;
  for (int scan = 0; scan < 64; ++scan) dense.push_back({scan_order(TransformSize::k8x8).scan[scan], 1});
  ones.append_levels(dense.data(), 64, TransformSize::k8x8);
  EXPECT_EQ(ones.levels.size(), 25u);
}

TEST(CodecFrame, DamagedPackedLevelsReadShortNeverOutside) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 2000; ++trial) {
    CoefficientFrame frame;
    frame.levels.resize(rng() % 12);
    for (uint8_t& b : frame.levels) b = static_cast<uint8_t>(rng() % 4 == 0 ? 0 : rng());
    size_t offset = 0;
    int positions[kMaxTransformArea], values[kMaxTransformArea];
    TransformType type = TransformType::kDctDct;
    const int read = frame.read_levels(&offset, 256, TransformSize::k16x16, positions, values, &type);
    ASSERT_LT(static_cast<int>(type), kTransformTypes);
    ASSERT_LE(read, 256);
    for (int i = 0; i < read; ++i) {
      ASSERT_LT(positions[i], 256);
      ASSERT_GE(std::abs(values[i]), 1);
      ASSERT_LE(std::abs(values[i]), 4095);
    }
  }
}

TEST(CodecFrame, RejectsBadHeadersAndSizes) {
  const ImageYCbCr420 source = synthetic_image(32, 32);
  const std::vector<uint8_t> good =
      encode_intra_frame(source, {.qindex = 128, .deblocking = true, .cdef = false}, nullptr);  // no CDEF syntax
  ImageYCbCr420 out;
  EXPECT_TRUE(decode_intra_frame(good, 32, 32, &out).ok());
  auto with = [&](int index, uint8_t value) {
    std::vector<uint8_t> bytes = good;
    bytes[static_cast<size_t>(index)] = value;
    return decode_intra_frame(bytes, 32, 32, &out);
  };
  EXPECT_EQ(with(0, kBidirectionalTypeBit | kIntraSyntaxVersion).code(), ErrorCode::kCorruptData);  // B-face
  EXPECT_EQ(with(0, kIntraSyntaxVersion + 1).code(), ErrorCode::kUnsupported);                      // future syntax
  EXPECT_EQ(with(0, kIntraSyntaxVersion - 1).code(), ErrorCode::kUnsupported);  // older entropy coding
  EXPECT_EQ(with(0, 0).code(), ErrorCode::kUnsupported);  // before byte 0 held the version: type 0, version 8
  // The message says which side to update (docs/codec.md 1.1).
  const std::string newer = std::to_string(kIntraSyntaxVersion + 1), older = std::to_string(kIntraSyntaxFirst - 1);
  EXPECT_NE(with(0, kIntraSyntaxVersion + 1).message().find("version " + newer + " is newer than this build knows"),
            std::string::npos);
  EXPECT_NE(with(0, kIntraSyntaxFirst - 1).message().find("version " + older + " predates format 1.0"),
            std::string::npos);
  EXPECT_TRUE(with(kQIndexByte, 0).ok());                        // every qindex is valid: the finest
  EXPECT_TRUE(with(kQIndexByte, 255).ok());                      // and the coarsest
  EXPECT_TRUE(with(kIntraFlagsByte, kTransformTypesFlag).ok());  // loop filters off: other pixels, still valid
  // CDEF without its syntax reads it from the final zeros left out, or runs out.
  const Status cdef_without_syntax = with(kIntraFlagsByte, 2 | kTransformTypesFlag);
  EXPECT_TRUE(cdef_without_syntax.ok() || cdef_without_syntax.code() == ErrorCode::kCorruptData);
  EXPECT_TRUE(
      with(kIntraFlagsByte, 1 | kIntraWeightedMatrix | kTransformTypesFlag).ok());  // weighted: other pixels
  EXPECT_EQ(with(kIntraFlagsByte, 16 | kTransformTypesFlag).code(), ErrorCode::kCorruptData);  // an unknown flag
  EXPECT_EQ(with(kIntraFlagsByte, 0x80).code(), ErrorCode::kCorruptData);
  EXPECT_EQ(decode_intra_frame(good, 0, 32, &out).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(decode_intra_frame(good, 32, kMaxFrameDimension + 1, &out).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(decode_intra_frame({}, 32, 32, &out).code(), ErrorCode::kCorruptData);
  std::vector<uint8_t> trailing = good;  // more zeros than the final ones left out
  trailing.insert(trailing.end(), kImplicitZeroBytes + 1, 0);
  const Status status = decode_intra_frame(trailing, 32, 32, &out);
  EXPECT_EQ(status.code(), ErrorCode::kCorruptData);
  EXPECT_NE(status.message().find("trailing"), std::string::npos) << status.message();
  // Invalid source images give an empty payload, which no decoder accepts.
  ImageYCbCr420 broken = source;
  broken.cb.pop_back();
  EXPECT_TRUE(encode_intra_frame(broken, {8}, nullptr).empty());
  EXPECT_TRUE(encode_intra_frame(ImageYCbCr420{}, {8}, nullptr).empty());
}

// A payload may leave out up to kImplicitZeroBytes final zeros (the decoder reads them as
// zeros); any shorter prefix is reported.
TEST(CodecFrame, EveryTruncationIsReportedAsCorrupt) {
  const ImageYCbCr420 source = synthetic_image(40, 24);
  const std::vector<uint8_t> good = encode_intra_frame(source, {115}, nullptr);
  ImageYCbCr420 out;
  for (size_t length = 0; length < good.size(); ++length) {
    const std::span<const uint8_t> prefix(good.data(), length);
    const Status status = decode_intra_frame(prefix, 40, 24, &out);
    if (good.size() - length > kImplicitZeroBytes) {
      EXPECT_EQ(status.code(), ErrorCode::kCorruptData) << "length " << length;
    } else if (status.ok()) {
      EXPECT_EQ(out.y.size(), source.y.size()) << "length " << length;
    }
  }
}

TEST(CodecFrame, GarbageAndBitFlipsNeverCrash) {
  std::mt19937 rng(31);
  const ImageYCbCr420 source = synthetic_image(48, 40);
  const std::vector<uint8_t> good = encode_intra_frame(source, {138}, nullptr);
  int decoded_ok = 0, rejected = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    std::vector<uint8_t> bytes;
    if (trial % 2 == 0) {
      bytes.resize(rng() % 600);
      for (auto& v : bytes) v = static_cast<uint8_t>(rng());
      if (bytes.size() >= kFrameHeaderBytes) {  // mostly a valid header, to reach the entropy decoder
        bytes[0] = kIntraSyntaxVersion;
        bytes[kQIndexByte] = static_cast<uint8_t>(rng());
        bytes[kIntraFlagsByte] = 0;
      }
    } else {
      bytes = good;
      const int flips = 1 + static_cast<int>(rng() % 4);
      for (int f = 0; f < flips; ++f) {
        const size_t at = kFrameHeaderBytes + rng() % (bytes.size() - kFrameHeaderBytes);
        bytes[at] ^= static_cast<uint8_t>(1u << (rng() % 8));
      }
    }
    const int width = trial % 3 == 0 ? 48 : 1 + static_cast<int>(rng() % 70);
    const int height = trial % 3 == 0 ? 40 : 1 + static_cast<int>(rng() % 70);
    ImageYCbCr420 out;
    const Status status = decode_intra_frame(bytes, width, height, &out);
    if (status.ok()) {
      ++decoded_ok;
      ASSERT_EQ(out.y.size(), static_cast<size_t>(width * height));
      ASSERT_EQ(out.cb.size(), static_cast<size_t>(((width + 1) / 2) * ((height + 1) / 2)));
    } else {
      ++rejected;
      ASSERT_FALSE(status.message().empty());
    }
  }
  EXPECT_GT(rejected, 0);
  EXPECT_EQ(decoded_ok + rejected, 1500);
}

TEST(CodecFrame, WeightedMatricesAreSignalledAndDecodeExactly) {
  const ImageYCbCr420 source = synthetic_image(64, 48);
  CodingParams flat{100}, weighted{100};
  weighted.residual_matrix = ResidualMatrix::kWeighted;
  ImageYCbCr420 flat_reconstruction, weighted_reconstruction, decoded;
  const std::vector<uint8_t> flat_bytes = encode_intra_frame(source, flat, &flat_reconstruction);
  const std::vector<uint8_t> weighted_bytes = encode_intra_frame(source, weighted, &weighted_reconstruction);
  EXPECT_EQ(flat_bytes[kIntraFlagsByte] & kIntraWeightedMatrix, 0);
  EXPECT_EQ(weighted_bytes[kIntraFlagsByte] & kIntraWeightedMatrix, kIntraWeightedMatrix);
  // Coarser high frequencies: fewer bytes and other pixels at the same index.
  EXPECT_LT(weighted_bytes.size(), flat_bytes.size());
  EXPECT_FALSE(weighted_reconstruction.y == flat_reconstruction.y);
  ASSERT_TRUE(decode_intra_frame(weighted_bytes, 64, 48, &decoded).ok());
  expect_same_image(decoded, weighted_reconstruction);
  CoefficientFrame coefficients;
  ASSERT_TRUE(parse_intra_frame(weighted_bytes, 64, 48, &coefficients).ok());
  EXPECT_EQ(coefficients.residual_matrix, ResidualMatrix::kWeighted);
  // The same levels read with the flat matrix give other pixels: the flag matters.
  std::vector<uint8_t> relabelled = weighted_bytes;
  relabelled[kIntraFlagsByte] &= static_cast<uint8_t>(~kIntraWeightedMatrix);
  ImageYCbCr420 misread;
  ASSERT_TRUE(decode_intra_frame(relabelled, 64, 48, &misread).ok());
  EXPECT_FALSE(misread.y == decoded.y);
}

}  // namespace
}  // namespace svc::codec
