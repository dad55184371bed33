// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <random>
#include <vector>

#include "codec/common/color.h"
#include "codec/encoder/rgb_to_ycbcr.h"

namespace svc::codec {
namespace {

std::vector<uint8_t> random_rgb(int width, int height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> rgb(static_cast<size_t>(width) * height * 3);
  for (auto& v : rgb) v = static_cast<uint8_t>(rng() >> 24);
  return rgb;
}

struct ErrorStats {
  int max_error[3] = {0, 0, 0};
  double mean_abs_error[3] = {0, 0, 0};
  double mean_error[3] = {0, 0, 0};
};

ErrorStats compare_rgb(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  ErrorStats stats;
  const size_t pixels = a.size() / 3;
  for (size_t i = 0; i < pixels; ++i) {
    for (int c = 0; c < 3; ++c) {
      const int d = int{b[3 * i + c]} - int{a[3 * i + c]};
      stats.max_error[c] = std::max(stats.max_error[c], std::abs(d));
      stats.mean_abs_error[c] += std::abs(d);
      stats.mean_error[c] += d;
    }
  }
  for (int c = 0; c < 3; ++c) {
    stats.mean_abs_error[c] /= static_cast<double>(pixels);
    stats.mean_error[c] /= static_cast<double>(pixels);
  }
  return stats;
}

TEST(CodecColor, GreyMapsToNeutralChromaAndBackExactly) {
  for (int v = 0; v < 256; ++v) {
    const uint8_t g = static_cast<uint8_t>(v);
    const YCbCr ycc = rgb_to_ycbcr_pixel(g, g, g);
    EXPECT_EQ(ycc.y, v);
    EXPECT_EQ(ycc.cb, 128);
    EXPECT_EQ(ycc.cr, 128);
    uint8_t rgb[3];
    ycbcr_to_rgb_pixel(ycc.y, ycc.cb, ycc.cr, rgb);
    EXPECT_EQ(rgb[0], v);
    EXPECT_EQ(rgb[1], v);
    EXPECT_EQ(rgb[2], v);
  }
}

TEST(CodecColor, KnownJfifValues) {
  // Pure primaries per JFIF: Y = 0.299R + 0.587G + 0.114B, Cb/Cr offset by 128.
  YCbCr red = rgb_to_ycbcr_pixel(255, 0, 0);
  EXPECT_EQ(red.y, 76);    // 76.245
  EXPECT_EQ(red.cb, 85);   // 84.97
  EXPECT_EQ(red.cr, 255);  // 255.5 saturates
  YCbCr blue = rgb_to_ycbcr_pixel(0, 0, 255);
  EXPECT_EQ(blue.y, 29);  // 29.07
  EXPECT_EQ(blue.cb, 255);
  EXPECT_EQ(blue.cr, 107);  // 107.27
}

TEST(CodecColor, PerPixelRoundTripOfAllColorsIsWithinTwo) {
  // Every 8-bit color on a stride-3 lattice (about 620k colors).
  std::vector<uint8_t> source, back;
  for (int r = 0; r < 256; r += 3) {
    for (int g = 0; g < 256; g += 3) {
      for (int b = 0; b < 256; b += 3) {
        source.insert(source.end(), {uint8_t(r), uint8_t(g), uint8_t(b)});
        const YCbCr ycc = rgb_to_ycbcr_pixel(uint8_t(r), uint8_t(g), uint8_t(b));
        uint8_t rgb[3];
        ycbcr_to_rgb_pixel(ycc.y, ycc.cb, ycc.cr, rgb);
        back.insert(back.end(), rgb, rgb + 3);
      }
    }
  }
  const ErrorStats stats = compare_rgb(source, back);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(stats.max_error[c], 3) << "channel " << c;
    EXPECT_LT(stats.mean_abs_error[c], 0.6) << "channel " << c;
    EXPECT_LT(std::fabs(stats.mean_error[c]), 0.05) << "channel " << c;
  }
}

TEST(CodecColor, SmoothGradientRoundTripThrough420IsSmall) {
  const int width = 64, height = 48;
  std::vector<uint8_t> rgb(static_cast<size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      uint8_t* p = &rgb[(static_cast<size_t>(y) * width + x) * 3];
      p[0] = static_cast<uint8_t>(40 + 3 * x);
      p[1] = static_cast<uint8_t>(30 + 2 * y + x);
      p[2] = static_cast<uint8_t>(220 - 2 * x - y);
    }
  }
  const ImageYCbCr420 ycc = rgb_to_ycbcr420(rgb.data(), width, height);
  std::vector<uint8_t> back(rgb.size());
  ycbcr420_to_rgb(ycc, back.data());
  const ErrorStats stats = compare_rgb(rgb, back);
  for (int c = 0; c < 3; ++c) {
    // Nearest-neighbour chroma on a gradient costs about half a chroma step per pixel.
    EXPECT_LE(stats.max_error[c], 6) << "channel " << c;
    EXPECT_LT(stats.mean_abs_error[c], 2.5) << "channel " << c;
    EXPECT_LT(std::fabs(stats.mean_error[c]), 0.5) << "channel " << c;
  }
}

TEST(CodecColor, ImageOfConstant2x2GroupsRoundTripsLikeSinglePixels) {
  const int width = 40, height = 30;
  std::vector<uint8_t> colors = random_rgb(width / 2, height / 2, 7);
  std::vector<uint8_t> rgb(static_cast<size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < 3; ++c) {
        rgb[(static_cast<size_t>(y) * width + x) * 3 + c] = colors[((y / 2) * (width / 2) + x / 2) * 3 + c];
      }
    }
  }
  const ImageYCbCr420 ycc = rgb_to_ycbcr420(rgb.data(), width, height);
  std::vector<uint8_t> back(rgb.size());
  ycbcr420_to_rgb(ycc, back.data());
  const ErrorStats stats = compare_rgb(rgb, back);
  for (int c = 0; c < 3; ++c) EXPECT_LE(stats.max_error[c], 3) << "channel " << c;
}

TEST(CodecColor, OptimizedConversionsMatchReferenceOnOddSizes) {
  for (auto [width, height] : {std::pair{1, 1}, {17, 9}, {250, 130}, {2, 3}, {64, 64}}) {
    const std::vector<uint8_t> rgb = random_rgb(width, height, static_cast<uint32_t>(width * 1000 + height));
    const ImageYCbCr420 fast = rgb_to_ycbcr420(rgb.data(), width, height);
    const ImageYCbCr420 reference = rgb_to_ycbcr420_reference(rgb.data(), width, height);
    ASSERT_EQ(fast.y.size(), static_cast<size_t>(width * height));
    ASSERT_EQ(fast.cb.size(), static_cast<size_t>(((width + 1) / 2) * ((height + 1) / 2)));
    EXPECT_EQ(fast.y, reference.y);
    EXPECT_EQ(fast.cb, reference.cb);
    EXPECT_EQ(fast.cr, reference.cr);
    std::vector<uint8_t> out_fast(rgb.size()), out_reference(rgb.size());
    ycbcr420_to_rgb(fast, out_fast.data());
    ycbcr420_to_rgb_reference(fast, out_reference.data());
    EXPECT_EQ(out_fast, out_reference);
  }
}

TEST(CodecColor, OddEdgeChromaIsMeanOfReplicatedPixels) {
  // 3x1: the second chroma sample covers pixel 2 replicated four times.
  const std::vector<uint8_t> rgb = {0, 0, 0, 0, 0, 0, 255, 0, 0};
  const ImageYCbCr420 ycc = rgb_to_ycbcr420(rgb.data(), 3, 1);
  ASSERT_EQ(ycc.cr.size(), 2u);
  EXPECT_EQ(ycc.cr[0], 128);
  EXPECT_EQ(ycc.cr[1], rgb_to_ycbcr_pixel(255, 0, 0).cr);
}

}  // namespace
}  // namespace svc::codec
