#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "codec/log_search.h"
#include "codec/motion_compensation.h"

namespace svc::codec {
namespace {

// Smooth random texture: a coarse random grid (one value per `cell` pixels) bilinearly
// upsampled, plus an optional finer ripple; structure at several scales, no flat areas.
std::vector<uint8_t> texture_plane(int width, int height, int cell, uint32_t seed, double ripple = 12) {
  std::mt19937 rng(seed);
  const int gw = width / cell + 2, gh = height / cell + 2;
  std::vector<double> grid(static_cast<size_t>(gw) * gh);
  for (double& v : grid) v = 30 + static_cast<double>(rng() % 196);
  std::vector<uint8_t> plane(static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double gx = static_cast<double>(x) / cell, gy = static_cast<double>(y) / cell;
      const int ix = static_cast<int>(gx), iy = static_cast<int>(gy);
      const double fx = gx - ix, fy = gy - iy;
      auto g = [&](int u, int v) { return grid[static_cast<size_t>(v) * gw + u]; };
      double value = (1 - fy) * ((1 - fx) * g(ix, iy) + fx * g(ix + 1, iy)) +
                     fy * ((1 - fx) * g(ix, iy + 1) + fx * g(ix + 1, iy + 1));
      value += ripple * std::sin(x * 0.45 + y * 0.2);
      plane[static_cast<size_t>(y) * width + x] = static_cast<uint8_t>(std::lround(std::clamp(value, 0.0, 255.0)));
    }
  }
  return plane;
}

// A crop of a larger texture: image(x, y) = texture(x + ox, y + oy).
ImageYCbCr420 textured_crop(int width, int height, int ox, int oy, uint32_t seed = 7, int cell = 11,
                            double ripple = 12) {
  const int tw = width + 128, th = height + 128;
  const std::vector<uint8_t> luma = texture_plane(tw, th, cell, seed, ripple);
  const std::vector<uint8_t> chroma = texture_plane(tw, th, 23, seed + 1);
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  image.y.resize(static_cast<size_t>(width) * height);
  image.cb.resize(static_cast<size_t>(cw) * ch);
  image.cr.resize(image.cb.size());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x)
      image.y[static_cast<size_t>(y) * width + x] = luma[static_cast<size_t>(y + oy) * tw + x + ox];
  }
  for (int y = 0; y < ch; ++y) {
    for (int x = 0; x < cw; ++x) {
      const size_t t = static_cast<size_t>(2 * y + oy) * tw + 2 * x + ox;
      image.cb[static_cast<size_t>(y) * cw + x] = chroma[t];
      image.cr[static_cast<size_t>(y) * cw + x] = static_cast<uint8_t>(255 - chroma[t]);
    }
  }
  return image;
}

TEST(MotionCompensation, FastPredictionMatchesReferenceOnRandomData) {
  std::mt19937 rng(42);
  const int sizes[][2] = {{37, 29}, {16, 16}, {1, 1}, {3, 50}, {64, 48}, {8, 8}};
  for (const auto& size : sizes) {
    const int w = size[0], h = size[1];
    std::vector<uint8_t> plane(static_cast<size_t>(w) * h);
    for (uint8_t& v : plane) v = static_cast<uint8_t>(rng());
    for (int trial = 0; trial < 400; ++trial) {
      const int block_w = trial % 3 == 0 ? 16 : (trial % 3 == 1 ? 8 : 1 + static_cast<int>(rng() % 20));
      const int block_h = trial % 3 == 0 ? 16 : (trial % 3 == 1 ? 8 : 1 + static_cast<int>(rng() % 20));
      const int x0 = static_cast<int>(rng() % static_cast<unsigned>(w + 16));
      const int y0 = static_cast<int>(rng() % static_cast<unsigned>(h + 16));
      // Mostly near the face, sometimes far outside it.
      const int range = trial % 5 == 0 ? 2000 : 4 * std::max(w, h) + 8;
      const int vx = static_cast<int>(rng() % static_cast<unsigned>(2 * range + 1)) - range;
      const int vy = static_cast<int>(rng() % static_cast<unsigned>(2 * range + 1)) - range;
      std::vector<uint8_t> fast(static_cast<size_t>(block_w) * block_h, 0), reference(fast.size(), 1);
      predict_block(plane.data(), w, h, x0, y0, block_w, block_h, vx, vy, fast.data(), block_w);
      predict_block_reference(plane.data(), w, h, x0, y0, block_w, block_h, vx, vy, reference.data(), block_w);
      ASSERT_EQ(fast, reference) << w << "x" << h << " block " << block_w << "x" << block_h << " at (" << x0 << ", "
                                 << y0 << ") vector (" << vx << ", " << vy << ")";
    }
  }
}

// Half-pel averages at the ends of the sample range, where a rounding or overflow slip in
// the vector paths would show.
TEST(MotionCompensation, FastPredictionMatchesReferenceAtExtremeSamples) {
  std::mt19937 rng(9);
  const uint8_t extremes[] = {0, 1, 2, 127, 128, 253, 254, 255};
  const int w = 40, h = 40;
  std::vector<uint8_t> plane(static_cast<size_t>(w) * h);
  for (uint8_t& v : plane) v = extremes[rng() % 8];
  for (int trial = 0; trial < 600; ++trial) {
    const int block = trial % 2 == 0 ? 16 : 8;
    const int x0 = static_cast<int>(rng() % 24), y0 = static_cast<int>(rng() % 24);
    const int vx = static_cast<int>(rng() % 17) - 8, vy = static_cast<int>(rng() % 17) - 8;
    std::vector<uint8_t> fast(static_cast<size_t>(block) * block, 0), reference(fast.size(), 1);
    predict_block(plane.data(), w, h, x0, y0, block, block, vx, vy, fast.data(), block);
    predict_block_reference(plane.data(), w, h, x0, y0, block, block, vx, vy, reference.data(), block);
    ASSERT_EQ(fast, reference) << "block " << block << " at (" << x0 << ", " << y0 << ") vector (" << vx << ", "
                               << vy << ")";
  }
}

TEST(MotionCompensation, EarlyExitSadMatchesPredictionAndSad) {
  std::mt19937 rng(3);
  const ImageYCbCr420 reference = textured_crop(53, 40, 5, 5);
  std::vector<uint8_t> source(64 * 48);
  for (uint8_t& v : source) v = static_cast<uint8_t>(rng());
  for (int trial = 0; trial < 2000; ++trial) {
    const int mb_x = static_cast<int>(rng() % 4), mb_y = static_cast<int>(rng() % 3);
    const int range = trial % 4 == 0 ? 300 : 40;
    const MotionVector v{static_cast<int16_t>(static_cast<int>(rng() % (2 * range + 1)) - range),
                         static_cast<int16_t>(static_cast<int>(rng() % (2 * range + 1)) - range)};
    uint8_t prediction[256];
    predict_macroblock_luma(reference, mb_x, mb_y, v, prediction);
    const uint8_t* block = source.data() + 16 * mb_y * 64 + 16 * mb_x;
    const int exact = sad_16x16_reference(block, 64, prediction);
    ASSERT_EQ(sad_16x16(block, 64, prediction), exact);
    ASSERT_EQ(sad_macroblock_luma(reference, mb_x, mb_y, v, block, 64, 1 << 30), exact);
    const int limit = static_cast<int>(rng() % 40000);
    const int bounded = sad_macroblock_luma(reference, mb_x, mb_y, v, block, 64, limit);
    if (exact <= limit) {
      ASSERT_EQ(bounded, exact);
    } else {
      ASSERT_GT(bounded, limit);
    }
  }
}

TEST(MotionCompensation, InterpolationFollowsMpeg2Rounding) {
  // 2x2 plane: 10 20 / 30 41.
  const std::vector<uint8_t> plane = {10, 20, 30, 41};
  uint8_t out[1];
  predict_block_reference(plane.data(), 2, 2, 0, 0, 1, 1, 1, 0, out, 1);
  EXPECT_EQ(out[0], 15);  // (10 + 20 + 1) >> 1
  predict_block(plane.data(), 2, 2, 0, 0, 1, 1, 0, 1, out, 1);
  EXPECT_EQ(out[0], 20);  // (10 + 30 + 1) >> 1
  predict_block(plane.data(), 2, 2, 0, 0, 1, 1, 1, 1, out, 1);
  EXPECT_EQ(out[0], 25);  // (10 + 20 + 30 + 41 + 2) >> 2 = 103 >> 2
  predict_block(plane.data(), 2, 2, 1, 1, 1, 1, 1, 1, out, 1);
  EXPECT_EQ(out[0], 41);  // edge extension: all four samples clamp to (1, 1)
  predict_block(plane.data(), 2, 2, 0, 0, 1, 1, -1, -1, out, 1);
  EXPECT_EQ(out[0], 10);  // (-1/2, -1/2) clamps to (0, 0)
  predict_block(plane.data(), 2, 2, 0, 0, 1, 1, -3, 0, out, 1);
  EXPECT_EQ(out[0], 10);  // x = -1.5: samples -2 and -1 both clamp to column 0
  predict_block(plane.data(), 2, 2, 0, 0, 1, 1, 1000, 1000, out, 1);
  EXPECT_EQ(out[0], 41);
}

TEST(MotionCompensation, ChromaVectorTruncatesTowardZero) {
  EXPECT_EQ(chroma_vector(MotionVector{3, -3}), (MotionVector{1, -1}));
  EXPECT_EQ(chroma_vector(MotionVector{-1, 1}), (MotionVector{0, 0}));
  EXPECT_EQ(chroma_vector(MotionVector{8, -10}), (MotionVector{4, -5}));
}

TEST(MotionCompensation, VectorRange) {
  EXPECT_EQ(max_vector_component(256, 100), 576);
  EXPECT_EQ(max_vector_component(16384, 16384), 32767);
  EXPECT_TRUE(vector_in_range(MotionVector{576, -576}, 256, 100));
  EXPECT_FALSE(vector_in_range(MotionVector{577, 0}, 256, 100));
  EXPECT_FALSE(vector_in_range(MotionVector{0, -577}, 256, 100));
}

TEST(MotionCompensation, IntegerVectorCopiesShiftedMacroblock) {
  const ImageYCbCr420 reference = textured_crop(64, 48, 10, 10);
  MacroblockPrediction prediction;
  predict_macroblock(reference, 1, 1, MotionVector{6, -4}, &prediction);  // (+3, -2) pixels
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      ASSERT_EQ(prediction.y[16 * y + x], reference.y[static_cast<size_t>(16 + y - 2) * 64 + 16 + x + 3]);
    }
  }
  // Chroma vector (3, -2) half-pels: x is interpolated, y whole.
  const int cw = 32;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      const size_t i = static_cast<size_t>(8 + y - 1) * cw + 8 + x + 1;
      ASSERT_EQ(prediction.cb[8 * y + x], (reference.cb[i] + reference.cb[i + 1] + 1) >> 1);
    }
  }
  MacroblockPrediction other, mean;
  predict_macroblock(reference, 1, 1, MotionVector{0, 0}, &other);
  average_predictions(prediction, other, &mean);
  for (int i = 0; i < 256; ++i) ASSERT_EQ(mean.y[i], (prediction.y[i] + other.y[i] + 1) >> 1);
}

// Luma from a function of the pixel position, sampled at (x + ox, y + oy); grey chroma.
template <typename Function>
ImageYCbCr420 sampled_image(int width, int height, int ox, int oy, Function function) {
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  image.y.resize(static_cast<size_t>(width) * height);
  image.cb.assign(static_cast<size_t>((width + 1) / 2) * ((height + 1) / 2), 128);
  image.cr = image.cb;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      image.y[static_cast<size_t>(y) * width + x] =
          static_cast<uint8_t>(std::lround(std::clamp(function(x + ox, y + oy), 0.0, 255.0)));
    }
  }
  return image;
}

// Gaussian blobs of random size, sign and position on grey: isotropic features.
std::vector<double> blob_field(int size, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<double> field(static_cast<size_t>(size) * size, 128.0);
  for (int i = 0; i < size * size / 300; ++i) {
    const double cx = rng() % size, cy = rng() % size, sigma = 4 + rng() % 8;
    const double amplitude = static_cast<double>(rng() % 81) - 40;
    const int r = static_cast<int>(3 * sigma);
    for (int y = std::max(0, static_cast<int>(cy) - r); y < std::min(size, static_cast<int>(cy) + r); ++y) {
      for (int x = std::max(0, static_cast<int>(cx) - r); x < std::min(size, static_cast<int>(cx) + r); ++x) {
        const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
        field[static_cast<size_t>(y) * size + x] += amplitude * std::exp(-d2 / (2 * sigma * sigma));
      }
    }
  }
  return field;
}

// Interior macroblocks (no edge extension involved) of a 128x96 face whose vector is (10, -6).
int exact_interior(const FaceCandidates& candidates) {
  int exact = 0;
  for (int my = 1; my < 5; ++my) {
    for (int mx = 1; mx < 7; ++mx) {
      const CandidateList& list = candidates[static_cast<size_t>(my) * 8 + mx];
      exact += list.size() == 1 && list[0] == MotionVector{10, -6};
    }
  }
  return exact;
}

TEST(LogSearch, FindsKnownTranslationOnSmoothShading) {
  // Smooth shading curved in every direction (no aperture problem, no false minimum
  // within the window for most blocks). source(x, y) = reference(x + 5, y - 3).
  auto shading = [](int x, int y) {
    return 128 + 50 * std::sin(x / 11.0) * std::cos(y / 9.0) + 30 * std::sin((x + y) / 17.0);
  };
  const ImageYCbCr420 reference = sampled_image(128, 96, 40, 40, shading);
  const ImageYCbCr420 source = sampled_image(128, 96, 45, 37, shading);
  for (LogSearchPattern pattern : {LogSearchPattern::kCross, LogSearchPattern::kNinePoint}) {
    LogSearchParams params;
    params.pattern = pattern;
    LogSearchStats stats;
    const FaceCandidates candidates = log_search_candidates(source, reference, params, &stats);
    ASSERT_EQ(candidates.size(), 8u * 6u);
    EXPECT_GE(exact_interior(candidates), 20) << static_cast<int>(pattern);
    // A logarithmic search scores a few dozen vectors, not the window's 4225.
    EXPECT_LT(stats.sad_evaluations, 48 * 60);
    EXPECT_GT(stats.sad_evaluations, 48 * 13);
  }
}

TEST(LogSearch, FindsKnownTranslationOnTexture) {
  const std::vector<double> field = blob_field(256, 7);
  auto texture = [&](int x, int y) { return field[static_cast<size_t>(y) * 256 + x]; };
  const ImageYCbCr420 reference = sampled_image(128, 96, 40, 40, texture);
  const ImageYCbCr420 source = sampled_image(128, 96, 45, 37, texture);
  // Textured blocks can trap the search in a false minimum; most still find the motion.
  EXPECT_GE(exact_interior(log_search_candidates(source, reference)), 16);
}

TEST(LogSearch, FindsHalfPelTranslationAndHandlesOddSizes) {
  // A reference upsampled by pixel averaging so that a half-pel shift is exact in x.
  const ImageYCbCr420 base = textured_crop(38, 30, 30, 30);
  ImageYCbCr420 reference = base, source = base;
  for (int y = 0; y < 30; ++y) {
    for (int x = 0; x < 37; ++x) {
      const size_t i = static_cast<size_t>(y) * 38 + x;
      source.y[i] = static_cast<uint8_t>((base.y[i] + base.y[i + 1] + 1) >> 1);
    }
  }
  // source(x) = mean of reference(x) and reference(x + 1): vector (+1, 0) half-pels.
  const FaceCandidates candidates = log_search_candidates(source, reference);
  ASSERT_EQ(candidates.size(), 3u * 2u);
  EXPECT_EQ(candidates[0][0], (MotionVector{1, 0}));
  LogSearchParams integer_only;
  integer_only.half_pel = false;
  for (const CandidateList& list : log_search_candidates(source, reference, integer_only)) {
    EXPECT_EQ(list[0].x % 2, 0);
    EXPECT_EQ(list[0].y % 2, 0);
  }
  EXPECT_TRUE(log_search_candidates(source, textured_crop(20, 20, 0, 0)).empty());
}

TEST(LogSearch, StaysInsideTheWindow) {
  // Unrelated images: whatever the search finds must lie within +-32 pixels.
  const ImageYCbCr420 a = textured_crop(96, 64, 0, 0, 3), b = textured_crop(96, 64, 0, 0, 99);
  for (const CandidateList& list : log_search_candidates(a, b)) {
    ASSERT_EQ(list.size(), 1u);
    EXPECT_LE(std::abs(list[0].x), 65);
    EXPECT_LE(std::abs(list[0].y), 65);
  }
}

}  // namespace
}  // namespace svc::codec
