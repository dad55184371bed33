// The quality search of `svc bench` (bench/settings_search.h) on known PSNR curves.
#include <gtest/gtest.h>

#include <cmath>

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
