// SPDX-License-Identifier: BSD-2-Clause
// The quality search of `svc bench` (bench/settings_search.h) on known PSNR curves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bd_rate.h"
#include "settings_search.h"

namespace svc::bench {
namespace {

// Counts how many targets have a measured point within the tolerance.
int targets_met(const std::map<int, double>& measured, const SearchTargets& targets) {
  int met = 0;
  for (double t : targets.psnr_y) {
    for (const auto& [setting, psnr] : measured) {
      if (std::abs(psnr - t) <= targets.tolerance) {
        ++met;
        break;
      }
    }
  }
  return met;
}

TEST(BenchSearch, CrfLikeCurveGetsAPointNearEveryTarget) {
  // PSNR falls with the setting, faster at the low end, as CRF does.
  auto psnr_of = [](int crf) { return 55.0 - 0.45 * crf - 0.002 * crf * crf; };
  SettingRange range{0, 51, false, {22, 34}};
  const SearchTargets targets = default_targets(false);
  int calls = 0;
  auto measured = search_settings(range, targets, [&](int s) -> Result<double> {
    ++calls;
    return psnr_of(s);
  });
  ASSERT_TRUE(measured.ok());
  EXPECT_EQ(calls, static_cast<int>(measured->size()));  // no setting measured twice
  EXPECT_LE(calls, targets.max_runs);
  EXPECT_GE(measured->size(), 6u);
  EXPECT_GE(targets_met(*measured, targets), 6);
  for (const auto& [setting, psnr] : *measured) EXPECT_DOUBLE_EQ(psnr, psnr_of(setting));
  // Deterministic: the same curve gives the same settings.
  auto again = search_settings(range, targets, [&](int s) -> Result<double> { return psnr_of(s); });
  EXPECT_EQ(*again, *measured);
}

TEST(BenchSearch, QualityLikeCurveGoesTheOtherWay) {
  auto psnr_of = [](int quality) { return 24.0 + 0.2 * quality; };  // 24..44 dB over 0..100
  SettingRange range{0, 100, true, {50}};
  const SearchTargets targets = default_targets(false);
  auto measured = search_settings(range, targets, [&](int s) -> Result<double> { return psnr_of(s); });
  ASSERT_TRUE(measured.ok());
  EXPECT_EQ(targets_met(*measured, targets), 7);
}

TEST(BenchSearch, StopsAtTheRangeEndWhenTheCodecCannotReachATarget) {
  // Never above 36 dB: the targets above it stop at the range end.
  SettingRange range{1, 31, false, {4, 12}};
  auto measured =
      search_settings(range, default_targets(false), [&](int s) -> Result<double> { return 36.0 - 0.3 * (s - 1); });
  ASSERT_TRUE(measured.ok());
  EXPECT_TRUE(measured->count(1));
  EXPECT_LE(measured->size(), 10u);
}

TEST(BenchSearch, NextSettingNarrowsABracketAndStopsWhenMet) {
  SettingRange range{0, 51, false, {}};
  const std::map<int, double> measured = {{20, 40.0}, {30, 34.0}};
  const auto next = next_setting(range, measured, 37.0, 0.5);
  ASSERT_TRUE(next.has_value());
  EXPECT_EQ(*next, 25);
  EXPECT_FALSE(next_setting(range, measured, 34.3, 0.5).has_value());
  EXPECT_FALSE(next_setting(range, {{20, 40.0}, {21, 34.0}}, 37.0, 0.5).has_value());
}

// svc bench --quick on a 3x1x3 house of 64x64 faces: svc's quality curve through the
// PSNR-Y it measured there (41.64, 47.41, 48.92 dB at qualities 55, 71, 75) and x265's
// CRF curve (37.7 and 30.2 dB at its seeds 22 and 34). The quick search stopped svc at
// 41.6..48.9 dB and x265 at 30.2..37.7 dB: no overlap, no BD-rate. Each curve must now
// span both targets, so the two overlap over 32..38 dB.
TEST(BenchSearch, QuickCurvesOfSvcAndAnAnchorSpanTheTargetsAndOverlap) {
  auto svc_psnr = [](int q) {
    const double x[3] = {55, 71, 75}, y[3] = {41.64, 47.41, 48.92};
    double psnr = 0;
    for (int i = 0; i < 3; ++i) {
      double term = y[i];
      for (int j = 0; j < 3; ++j) {
        if (j != i) term *= (q - x[j]) / (x[i] - x[j]);
      }
      psnr += term;
    }
    return psnr;
  };
  auto x265_psnr = [](int crf) { return 37.7 - 0.625 * (crf - 22); };
  const SearchTargets quick = default_targets(true);
  auto svc = search_settings({5, 100, true, {75}}, quick, [&](int q) -> Result<double> { return svc_psnr(q); });
  auto x265 =
      search_settings({0, 51, false, {22, 34}}, quick, [&](int c) -> Result<double> { return x265_psnr(c); });
  ASSERT_TRUE(svc.ok() && x265.ok());
  std::vector<RatePoint> svc_points, x265_points;
  for (const auto& [setting, psnr] : *svc) svc_points.push_back({std::exp(0.1 * psnr), psnr});
  for (const auto& [setting, psnr] : *x265) x265_points.push_back({std::exp(0.12 * psnr), psnr});
  for (const auto* points : {&svc_points, &x265_points}) {
    EXPECT_LE(points->size(), static_cast<size_t>(quick.max_runs));
    double low = 1e9, high = -1e9;
    for (const RatePoint& p : *points) low = std::min(low, p.psnr), high = std::max(high, p.psnr);
    EXPECT_LE(low, 32.0);
    EXPECT_GE(high, 38.0);
  }
  const auto bd = bd_rate(x265_points, svc_points);
  ASSERT_TRUE(bd.has_value());
  EXPECT_LE(bd->psnr_low, 32.0);
  EXPECT_GE(bd->psnr_high, 38.0);
}

// An end target met on the near side alone is not met: the curve must reach past it.
TEST(BenchSearch, EndTargetsNeedAPointBeyondThem) {
  SettingRange range{0, 100, true, {}};
  const std::map<int, double> measured = {{40, 33.0}, {60, 40.0}};
  EXPECT_FALSE(next_setting(range, measured, 32.0, 2.0).has_value());  // an inner target: 33 is near
  const auto lower = next_setting(range, measured, 32.0, 2.0, -1);
  ASSERT_TRUE(lower.has_value());
  EXPECT_LT(*lower, 40);
  EXPECT_FALSE(next_setting(range, {{35, 31.2}, {40, 33.0}}, 32.0, 2.0, -1).has_value());
  const auto higher = next_setting(range, {{20, 30.0}, {40, 37.0}}, 38.0, 2.0, 1);
  ASSERT_TRUE(higher.has_value());
  EXPECT_GT(*higher, 40);
}

TEST(BenchSearch, MeasurementErrorsStopTheSearch) {
  SettingRange range{0, 51, false, {22}};
  auto measured = search_settings(range, default_targets(true), [](int) -> Result<double> {
    return Status(ErrorCode::kInternal, "encoder failed");
  });
  ASSERT_FALSE(measured.ok());
  EXPECT_EQ(measured.status().code(), ErrorCode::kInternal);
}

}  // namespace
}  // namespace svc::bench
