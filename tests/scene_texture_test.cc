// SPDX-License-Identifier: BSD-2-Clause
// Texture pyramids: exact texels where a pixel covers less than a texel, averages where
// it covers many, means kept through resizing, and coordinates that wrap.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "scene/scene_texture.h"

namespace svc::samples::detail {
namespace {

// A `w` x `h` image whose texel (x, y) holds (x, y, x * y) scaled into [0, 1].
std::vector<float> ramp(int w, int h) {
  std::vector<float> rgb(static_cast<size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float* p = &rgb[(static_cast<size_t>(y) * w + x) * 3];
      p[0] = static_cast<float>(x) / w;
      p[1] = static_cast<float>(y) / h;
      p[2] = static_cast<float>(x * y) / (w * h);
    }
  }
  return rgb;
}

glm::dvec3 image_mean(const std::vector<float>& rgb) {
  glm::dvec3 sum(0.0);
  for (size_t i = 0; i < rgb.size(); i += 3) sum += glm::dvec3(rgb[i], rgb[i + 1], rgb[i + 2]);
  return sum / static_cast<double>(rgb.size() / 3);
}

// One-texel red and blue checker.
std::vector<float> checker(int n) {
  std::vector<float> rgb(static_cast<size_t>(n) * n * 3, 0.0f);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) rgb[(static_cast<size_t>(y) * n + x) * 3 + ((x + y) % 2 ? 2 : 0)] = 1;
  }
  return rgb;
}

TEST(SceneTexture, SmallFootprintReturnsTexelsExactly) {
  const std::vector<float> rgb = ramp(8, 4);
  const Texture texture(8, 4, rgb);
  ASSERT_EQ(texture.width(0), 8);
  ASSERT_EQ(texture.height(0), 4);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 8; ++x) {
      // Texel centres; v runs upwards from the bottom row.
      const double u = (x + 0.5) / 8, v = 1 - (y + 0.5) / 4;
      const glm::dvec3 s = texture.sample(u, v, 0.01 / 8);
      const float* want = &rgb[(y * 8 + x) * 3];
      EXPECT_NEAR(s.x, want[0], 1e-6) << x << "," << y;
      EXPECT_NEAR(s.y, want[1], 1e-6) << x << "," << y;
      EXPECT_NEAR(s.z, want[2], 1e-6) << x << "," << y;
    }
  }
}

TEST(SceneTexture, CoordinatesWrapAroundEveryRepeat) {
  const Texture texture(8, 8, ramp(8, 8));
  for (double u : {0.13, 0.71}) {
    for (double v : {0.05, 0.52}) {
      const glm::dvec3 a = texture.sample(u, v, 0.02);
      const glm::dvec3 b = texture.sample(u + 3, v - 5, 0.02);
      EXPECT_NEAR(a.x, b.x, 1e-9);
      EXPECT_NEAR(a.y, b.y, 1e-9);
      EXPECT_NEAR(a.z, b.z, 1e-9);
    }
  }
}

TEST(SceneTexture, PyramidKeepsTheMeanAndEndsInOneTexel) {
  for (auto [w, h] : {std::pair{16, 16}, std::pair{12, 5}, std::pair{1500, 40}}) {
    const std::vector<float> rgb = ramp(w, h);
    const Texture texture(w, h, rgb);
    EXPECT_EQ(texture.width(texture.levels() - 1), 1);
    EXPECT_EQ(texture.height(texture.levels() - 1), 1);
    EXPECT_LE(texture.width(0), std::min(w, Texture::kMaxSize));
    EXPECT_LE(texture.height(0), h);
    const glm::dvec3 want = image_mean(rgb), got = texture.mean();
    EXPECT_NEAR(got.x, want.x, 1e-4) << w << "x" << h;
    EXPECT_NEAR(got.y, want.y, 1e-4) << w << "x" << h;
    EXPECT_NEAR(got.z, want.z, 1e-4) << w << "x" << h;
  }
}

TEST(SceneTexture, FootprintsOfManyTexelsAverageInsteadOfAliasing) {
  const Texture texture(64, 64, checker(64));
  double worst_coarse = 0;
  for (int k = 0; k < 200; ++k) {
    const double u = 0.37 * k + 0.011, v = 0.61 * k + 0.007;
    // Eight texels per pixel: the two colors mixed evenly.
    const glm::dvec3 coarse = texture.sample(u, v, 8.0 / 64);
    worst_coarse = std::max(worst_coarse, std::abs(coarse.x - coarse.z));
    EXPECT_NEAR(coarse.x + coarse.z, 1.0, 1e-6);
  }
  EXPECT_LT(worst_coarse, 0.02);
  // At texel centres with a tiny footprint the checker is pure.
  const glm::dvec3 centre = texture.sample(0.5 / 64, 1 - 0.5 / 64, 0.01 / 64);
  EXPECT_NEAR(centre.x, 1.0, 1e-9);
  EXPECT_NEAR(centre.z, 0.0, 1e-9);
}

}  // namespace
}  // namespace svc::samples::detail
