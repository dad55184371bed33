// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "codec/common/motion_compensation.h"
#include "codec/encoder/log_search.h"
#include "codec/encoder/sad.h"
#include "codec/encoder/search_planes.h"

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

// A random block placement and vector: mostly near the face, sometimes far outside it.
struct BlockCase {
  PlaneKind kind;
  int x0, y0, width, height, vx, vy;
  InterpolationFilter filter = InterpolationFilter::kRegular;
};

BlockCase random_case(std::mt19937& rng, int trial, int w, int h) {
  BlockCase c;
  c.kind = trial % 2 == 0 ? PlaneKind::kLuma : PlaneKind::kChroma;
  const int shape = trial % 4;
  c.width = shape == 0 ? 16 : (shape == 1 ? 8 : (shape == 2 ? 4 : 1 + static_cast<int>(rng() % 20)));
  c.height = shape == 0 ? 16 : (shape == 1 ? 8 : (shape == 2 ? 4 : 1 + static_cast<int>(rng() % 20)));
  c.x0 = static_cast<int>(rng() % static_cast<unsigned>(w + 16));
  c.y0 = static_cast<int>(rng() % static_cast<unsigned>(h + 16));
  const int range = trial % 5 == 0 ? 4000 : 8 * std::max(w, h) + 16;
  c.vx = static_cast<int>(rng() % static_cast<unsigned>(2 * range + 1)) - range;
  c.vy = static_cast<int>(rng() % static_cast<unsigned>(2 * range + 1)) - range;
  c.filter = static_cast<InterpolationFilter>(trial / 4 % kInterpolationFilterCount);
  return c;
}

void expect_fast_equals_reference(const std::vector<uint8_t>& plane, int w, int h, const BlockCase& c) {
  std::vector<int16_t> fast(static_cast<size_t>(c.width) * c.height, 0), reference(fast.size(), 1);
  predict_block(plane.data(), w, h, c.kind, c.x0, c.y0, c.width, c.height, c.vx, c.vy, fast.data(), c.width,
                c.filter);
  predict_block_reference(plane.data(), w, h, c.kind, c.x0, c.y0, c.width, c.height, c.vx, c.vy, reference.data(),
                          c.width, c.filter);
  ASSERT_EQ(fast, reference) << (c.kind == PlaneKind::kLuma ? "luma " : "chroma ") << w << "x" << h << " block "
                             << c.width << "x" << c.height << " at (" << c.x0 << ", " << c.y0 << ") vector ("
                             << c.vx << ", " << c.vy << ") filter " << static_cast<int>(c.filter);
}

TEST(MotionCompensation, FastPredictionMatchesReferenceOnRandomData) {
  std::mt19937 rng(42);
  const int sizes[][2] = {{37, 29}, {16, 16}, {1, 1}, {3, 50}, {64, 48}, {8, 8}};
  for (const auto& size : sizes) {
    const int w = size[0], h = size[1];
    std::vector<uint8_t> plane(static_cast<size_t>(w) * h);
    for (uint8_t& v : plane) v = static_cast<uint8_t>(rng());
    for (int trial = 0; trial < 400; ++trial)
      expect_fast_equals_reference(plane, w, h, random_case(rng, trial, w, h));
  }
}

// The ends of the sample range, where the filters' negative taps reach the extremes of
// the 16-bit intermediates.
TEST(MotionCompensation, FastPredictionMatchesReferenceAtExtremeSamples) {
  std::mt19937 rng(9);
  const uint8_t extremes[] = {0, 1, 2, 127, 128, 253, 254, 255};
  const int w = 40, h = 40;
  std::vector<uint8_t> plane(static_cast<size_t>(w) * h);
  for (uint8_t& v : plane) v = extremes[rng() % 8];
  // Alternating 0 / 255 columns and rows: the largest and smallest sums of both passes.
  std::vector<uint8_t> checker(plane.size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) checker[static_cast<size_t>(y) * w + x] = ((x ^ y) & 1) ? 255 : 0;
  }
  for (int trial = 0; trial < 600; ++trial) {
    BlockCase c = random_case(rng, trial, w, h);
    c.vx = static_cast<int>(rng() % 33) - 16;
    c.vy = static_cast<int>(rng() % 33) - 16;
    expect_fast_equals_reference(trial % 2 ? plane : checker, w, h, c);
  }
}

TEST(MotionCompensation, SadOfPredictionMatchesPlainSad) {
  std::mt19937 rng(3);
  const ImageYCbCr420 reference = textured_crop(53, 40, 5, 5);
  std::vector<uint8_t> source(64 * 48);
  for (uint8_t& v : source) v = static_cast<uint8_t>(rng());
  for (int trial = 0; trial < 500; ++trial) {
    const int mb_x = static_cast<int>(rng() % 4), mb_y = static_cast<int>(rng() % 3);
    const int range = trial % 4 == 0 ? 600 : 80;
    const MotionVector v{static_cast<int16_t>(static_cast<int>(rng() % (2 * range + 1)) - range),
                         static_cast<int16_t>(static_cast<int>(rng() % (2 * range + 1)) - range)};
    int16_t intermediate[256];
    uint8_t prediction[256];
    predict_macroblock_luma(reference, mb_x, mb_y, v, intermediate);
    round_prediction(intermediate, 256, prediction);
    const uint8_t* block = source.data() + 16 * mb_y * 64 + 16 * mb_x;
    const int exact = sad_16x16_reference(block, 64, prediction);
    ASSERT_EQ(sad_16x16(block, 64, prediction), exact);
    ASSERT_EQ(sad_macroblock_luma(reference, mb_x, mb_y, v, block, 64), exact);
  }
}

// One row of samples 10, 20, ..., 80 predicted at one position.
int predict_on_ramp(PlaneKind kind, int x0, int vector_x) {
  const std::vector<uint8_t> ramp = {10, 20, 30, 40, 50, 60, 70, 80};
  int16_t intermediate = 0;
  predict_block(ramp.data(), 8, 1, kind, x0, 0, 1, 1, vector_x, 0, &intermediate, 1);
  uint8_t sample = 0;
  round_prediction(&intermediate, 1, &sample);
  return sample;
}

TEST(MotionCompensation, InterpolationFollowsHevcFilters) {
  // Half pel between 40 and 50: -10 + 80 - 330 + 1600 + 2000 - 660 + 280 - 80 = 2880.
  EXPECT_EQ(predict_on_ramp(PlaneKind::kLuma, 3, 2), 45);
  // Quarter pel: -10 + 80 - 300 + 2320 + 850 - 300 + 70 = 2710; (2710 + 32) >> 6 = 42.
  EXPECT_EQ(predict_on_ramp(PlaneKind::kLuma, 3, 1), 42);
  // Three quarters: 20 - 150 + 680 + 2900 - 600 + 280 - 80 = 3050; (3050 + 32) >> 6 = 48.
  EXPECT_EQ(predict_on_ramp(PlaneKind::kLuma, 3, 3), 48);
  // Chroma 3/8 pel between 40 and 50: -6*30 + 46*40 + 28*50 - 4*60 = 2820; 44.
  EXPECT_EQ(predict_on_ramp(PlaneKind::kChroma, 3, 3), 44);
  // Whole pels and edge extension: every tap clamps to the first or last sample.
  EXPECT_EQ(predict_on_ramp(PlaneKind::kLuma, 3, 4), 50);
  EXPECT_EQ(predict_on_ramp(PlaneKind::kLuma, 0, -1000), 10);
  EXPECT_EQ(predict_on_ramp(PlaneKind::kChroma, 7, 1000), 80);
  // Near the edge the clamped taps repeat 10: at x = 1/4 the taps at -3..4 read 10, 10,
  // 10, 10, 20, 30, 40, 50: -10 + 40 - 100 + 580 + 340 - 150 + 40 = 740.
  EXPECT_EQ(predict_on_ramp(PlaneKind::kLuma, 0, 1), (-10 + 40 - 100 + 580 + 340 - 150 + 40 + 32) >> 6);
}

TEST(MotionCompensation, RoundingAndBidirectionalAverageKeepPrecision) {
  // Intermediates are 64 x the sample less 8192: 10.25 and 10.5 average to 10.375 -> 10,
  // where rounding each first (10 and 11) would give 11.
  const int16_t a[1] = {static_cast<int16_t>(64 * 10 + 16 - kIntermediateOffset)};
  const int16_t b[1] = {static_cast<int16_t>(64 * 10 + 32 - kIntermediateOffset)};
  uint8_t out[1];
  average_prediction(a, b, 1, out);
  EXPECT_EQ(out[0], 10);
  round_prediction(b, 1, out);
  EXPECT_EQ(out[0], 11);
  // Negative-tap overshoot clips to 0..255.
  const int16_t low[1] = {-9000}, high[1] = {24000};
  round_prediction(low, 1, out);
  EXPECT_EQ(out[0], 0);
  round_prediction(high, 1, out);
  EXPECT_EQ(out[0], 255);
  average_prediction(high, high, 1, out);
  EXPECT_EQ(out[0], 255);
}

TEST(MotionCompensation, VectorRange) {
  EXPECT_EQ(max_vector_component(256, 100), 1152);
  EXPECT_EQ(max_vector_component(16384, 16384), 32767);
  EXPECT_TRUE(vector_in_range(MotionVector{1152, -1152}, 256, 100));
  EXPECT_FALSE(vector_in_range(MotionVector{1153, 0}, 256, 100));
  EXPECT_FALSE(vector_in_range(MotionVector{0, -1153}, 256, 100));
}

TEST(MotionCompensation, IntegerVectorCopiesShiftedMacroblock) {
  const ImageYCbCr420 reference = textured_crop(64, 48, 10, 10);
  MacroblockIntermediate intermediate;
  MacroblockPrediction prediction;
  predict_macroblock(reference, 1, 1, MotionVector{12, -8}, &intermediate);  // (+3, -2) pixels
  finish_prediction(intermediate, nullptr, &prediction);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      ASSERT_EQ(prediction.y[16 * y + x], reference.y[static_cast<size_t>(16 + y - 2) * 64 + 16 + x + 3]);
    }
  }
  // Chroma reads (12, -8) in eighth pels: x at 1.5 (the 4-tap half filter), y whole.
  const int cw = 32;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      const size_t i = static_cast<size_t>(8 + y - 1) * cw + 8 + x + 1;
      const int sum =
          -4 * reference.cb[i - 1] + 36 * reference.cb[i] + 36 * reference.cb[i + 1] - 4 * reference.cb[i + 2];
      ASSERT_EQ(prediction.cb[8 * y + x], std::clamp((sum + 32) >> 6, 0, 255));
    }
  }
  MacroblockIntermediate other;
  MacroblockPrediction mean;
  predict_macroblock(reference, 1, 1, MotionVector{0, 0}, &other);
  finish_prediction(intermediate, &other, &mean);
  for (int i = 0; i < 256; ++i)
    ASSERT_EQ(mean.y[i],
              (prediction.y[i] + reference.y[static_cast<size_t>(16 + i / 16) * 64 + 16 + i % 16] + 1) >> 1);
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

// Interior macroblocks (no edge extension involved) of a 128x96 face whose vector is
// (20, -12) quarter pels.
int exact_interior(const FaceCandidates& candidates) {
  int exact = 0;
  for (int my = 1; my < 5; ++my) {
    for (int mx = 1; mx < 7; ++mx) {
      const CandidateList& list = candidates[static_cast<size_t>(my) * 8 + mx];
      exact += list.size() == 1 && list[0] == MotionVector{20, -12};
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
  // source(x) = mean of reference(x) and reference(x + 1): vector (+2, 0) quarter pels.
  const FaceCandidates candidates = log_search_candidates(source, reference);
  ASSERT_EQ(candidates.size(), 3u * 2u);
  EXPECT_EQ(candidates[0][0], (MotionVector{2, 0}));
  LogSearchParams integer_only;
  integer_only.half_pel = false;
  for (const CandidateList& list : log_search_candidates(source, reference, integer_only)) {
    EXPECT_EQ(list[0].x % 4, 0);
    EXPECT_EQ(list[0].y % 4, 0);
  }
  EXPECT_TRUE(log_search_candidates(source, textured_crop(20, 20, 0, 0)).empty());
}

TEST(LogSearch, StaysInsideTheWindow) {
  // Unrelated images: whatever the search finds must lie within +-32 pixels.
  const ImageYCbCr420 a = textured_crop(96, 64, 0, 0, 3), b = textured_crop(96, 64, 0, 0, 99);
  for (const CandidateList& list : log_search_candidates(a, b)) {
    ASSERT_EQ(list.size(), 1u);
    EXPECT_LE(std::abs(list[0].x), 130);
    EXPECT_LE(std::abs(list[0].y), 130);
  }
}

}  // namespace
}  // namespace svc::codec

namespace svc::codec {
namespace {

// The rounded prediction of a block (regular filter) as samples.
std::vector<uint8_t> rounded_prediction(const ImageYCbCr420& reference, int x, int y, int width, int height, int vx,
                                        int vy) {
  std::vector<int16_t> intermediate(static_cast<size_t>(width) * height);
  predict_block(reference.y.data(), reference.width, reference.height, PlaneKind::kLuma, x, y, width, height, vx,
                vy, intermediate.data(), width);
  std::vector<uint8_t> samples(intermediate.size());
  round_prediction(intermediate.data(), static_cast<int>(intermediate.size()), samples.data());
  return samples;
}

// Whole and half-pel positions are priced exactly; a quarter position against the
// rounded-up average of its two nearest half-pel neighbours (across, down or diagonal);
// blocks beyond the margin are refused.
TEST(SearchPlanes, SadsAreExactAtHalfPelAndAveragedBetween) {
  const ImageYCbCr420 reference = textured_crop(48, 40, 5, 9, 3);
  const ImageYCbCr420 source = textured_crop(48, 40, 7, 6, 3);
  constexpr int kMargin = 12;
  const SearchPlanes planes(reference, kMargin);
  std::mt19937 rng(5);
  int refused = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int width = trial % 2 ? 16 : 8, height = trial % 3 ? 16 : 8;
    const int x = static_cast<int>(rng() % static_cast<unsigned>(48 - width + 1));
    const int y = static_cast<int>(rng() % static_cast<unsigned>(40 - height + 1));
    const MotionVector v{static_cast<int16_t>(static_cast<int>(rng() % 161) - 80),
                         static_cast<int16_t>(static_cast<int>(rng() % 161) - 80)};
    const uint8_t* src = source.y.data() + static_cast<size_t>(y) * 48 + x;
    const int sad = planes.sad(src, 48, x, y, width, height, v);
    // Half-pel neighbours: an odd component splits into the positions on either side.
    const int ax = v.x - (v.x & 1), bx = v.x + (v.x & 1), ay = v.y - (v.y & 1), by = v.y + (v.y & 1);
    // The planes hold each phase for whole-sample positions -kMargin .. size + kMargin - 1.
    const int reach_left = (4 * x + ax) >> 2, reach_top = (4 * y + ay) >> 2;
    const int reach_right = ((4 * x + bx) >> 2) + width, reach_bottom = ((4 * y + by) >> 2) + height;
    if (reach_left < -kMargin || reach_top < -kMargin || reach_right > 48 + kMargin ||
        reach_bottom > 40 + kMargin) {
      EXPECT_EQ(sad, -1) << "vector (" << v.x << ", " << v.y << ") at (" << x << ", " << y << ")";
      ++refused;
      continue;
    }
    const std::vector<uint8_t> a = rounded_prediction(reference, x, y, width, height, ax, ay);
    const std::vector<uint8_t> b = rounded_prediction(reference, x, y, width, height, bx, by);
    int expected = 0;
    for (int j = 0; j < height; ++j) {
      for (int i = 0; i < width; ++i) {
        const size_t k = static_cast<size_t>(j) * width + i;
        expected += std::abs(src[static_cast<size_t>(j) * 48 + i] - ((a[k] + b[k] + 1) >> 1));
      }
    }
    ASSERT_EQ(sad, expected) << width << "x" << height << " at (" << x << ", " << y << ") vector (" << v.x << ", "
                             << v.y << ")";
  }
  EXPECT_GT(refused, 100);
  EXPECT_LT(refused, 2900);
}

}  // namespace
}  // namespace svc::codec
