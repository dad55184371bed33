// SPDX-License-Identifier: BSD-2-Clause
// The anchor cache of `svc bench --anchor-cache` returns exactly what was stored, and
// only for the same faces, plan, targets and libraries; the content statistics of the
// bench report measure what they say.
#include <gtest/gtest.h>

#include <fstream>

#include "anchor_cache.h"
#include "anchors.h"
#include "source_faces.h"
#include "support/test_support.h"

namespace svc::bench {
namespace {

SourceFaces faces_of(uint8_t value, int count) {
  SourceFaces source;
  for (int k = 0; k < count; ++k) {
    ImageRGB8 face;
    face.width = face.height = 8;
    face.pixels.assign(8 * 8 * 3, value);
    source.faces.push_back(face);
  }
  return source;
}

std::vector<QualityPoint> two_points() {
  QualityPoint a, b;
  a.setting_name = b.setting_name = "crf";
  a.setting = 30;
  a.bytes = 12345;
  a.psnr_y = 36.5;
  a.psnr_rgb = 35.25;
  a.ssim = 0.93;
  b.setting = 40;
  b.bytes = 5432;
  b.psnr_y = 32.125;
  return {a, b};
}

TEST(AnchorCache, ReturnsWhatWasStoredForTheSameKeyOnly) {
  testing::TempDir dir("svc-anchor-cache");
  auto plan = make_plan("x264", AnchorOptions{}, 64, 64);
  ASSERT_TRUE(plan.ok());
  const std::string fingerprint = source_fingerprint(faces_of(10, 6));
  const std::string key = anchor_cache_key(fingerprint, *plan, false);
  EXPECT_FALSE(load_cached_points(dir.path(), key).has_value());
  ASSERT_TRUE(store_cached_points(dir.path(), key, two_points()).ok());
  const auto loaded = load_cached_points(dir.path(), key);
  ASSERT_TRUE(loaded.has_value());
  ASSERT_EQ(loaded->size(), 2u);
  EXPECT_EQ((*loaded)[0].bytes, 12345u);
  EXPECT_EQ((*loaded)[0].setting, 30);
  EXPECT_DOUBLE_EQ((*loaded)[0].psnr_y, 36.5);
  EXPECT_DOUBLE_EQ((*loaded)[0].psnr_rgb, 35.25);
  EXPECT_DOUBLE_EQ((*loaded)[1].psnr_y, 32.125);

  // Other faces, another preset, quick targets: each a different key, each a miss.
  EXPECT_NE(source_fingerprint(faces_of(11, 6)), fingerprint);
  EXPECT_NE(source_fingerprint(faces_of(10, 5)), fingerprint);
  EXPECT_FALSE(load_cached_points(dir.path(), anchor_cache_key(source_fingerprint(faces_of(11, 6)), *plan, false)));
  EXPECT_FALSE(load_cached_points(dir.path(), anchor_cache_key(fingerprint, *plan, true)));
  AnchorOptions slower;
  slower.presets["x264"] = "slow";
  auto slow_plan = make_plan("x264", slower, 64, 64);
  ASSERT_TRUE(slow_plan.ok());
  EXPECT_FALSE(load_cached_points(dir.path(), anchor_cache_key(fingerprint, *slow_plan, false)));
}

TEST(AnchorCache, DamagedEntryIsAMissNotAnError) {
  testing::TempDir dir("svc-anchor-cache-bad");
  auto plan = make_plan("x265", AnchorOptions{}, 64, 64);
  ASSERT_TRUE(plan.ok());
  const std::string key = anchor_cache_key(source_fingerprint(faces_of(3, 2)), *plan, false);
  ASSERT_TRUE(store_cached_points(dir.path(), key, two_points()).ok());
  int entries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    ++entries;
    std::ofstream(entry.path(), std::ios::trunc) << "{\"format\": \"svc-anchor-cache\", \"key\": ";
  }
  EXPECT_EQ(entries, 1);  // no temporary file left beside it
  EXPECT_FALSE(load_cached_points(dir.path(), key).has_value());
}

TEST(ContentStats, MeasureLumaContrastGradientAndBackground) {
  SourceFaces source;
  ImageRGB8 stripes;  // columns alternating between luma 100 and 150
  stripes.width = 4;
  stripes.height = 2;
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) {
      const uint8_t v = x % 2 ? 150 : 100;
      stripes.pixels.insert(stripes.pixels.end(), {v, v, v});
    }
  }
  source.faces = {stripes};
  source.background_pixels = 2;
  const ContentStats stats = content_stats(source, 1);
  EXPECT_NEAR(stats.mean_luma, 125.0, 1e-9);
  EXPECT_NEAR(stats.luma_contrast, 25.0, 1e-9);
  EXPECT_NEAR(stats.mean_gradient, 50.0, 1e-9);
  EXPECT_NEAR(stats.background_share, 0.25, 1e-12);
}

}  // namespace
}  // namespace svc::bench
