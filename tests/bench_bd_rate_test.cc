// SPDX-License-Identifier: BSD-2-Clause
// BD-rate by PCHIP interpolation of log-rate against PSNR (bench/bd_rate.h).
#include <gtest/gtest.h>

#include <cmath>

#include "bd_rate.h"

namespace svc::bench {
namespace {

// Published example data: test case 1 and 2 of the FAU-LMS "bjontegaard" package
// (github.com/FAU-LMS/bjontegaard, example_usage.py; libx265 at two presets, rates in
// kbit/s), whose 'pchip' method its authors report to equal the JCT-VC CTC spreadsheet
// to ten decimals. The package prints no figure for these data, so the expected values
// are that method (SciPy PchipInterpolator on log10 rate, integrate over the overlap)
// evaluated independently in double precision: -4.4174853506 % over 34.987-40.037 dB and
// -4.4721820028 % over 38.651-43.825 dB.
TEST(BenchBdRate, MatchesThePchipMethodOnPublishedExampleData) {
  const std::vector<RatePoint> anchor1 = {{9487.76, 40.037},
                                          {4593.60, 38.615},
                                          {2486.44, 36.845},
                                          {1358.24, 34.851}};
  const std::vector<RatePoint> test1 = {{9787.80, 40.121}, {4469.00, 38.651}, {2451.52, 36.970}, {1356.24, 34.987}};
  const auto bd1 = bd_rate(anchor1, test1);
  ASSERT_TRUE(bd1.has_value());
  EXPECT_NEAR((bd1->ratio - 1) * 100, -4.4174853506, 1e-8);
  EXPECT_DOUBLE_EQ(bd1->psnr_low, 34.987);
  EXPECT_DOUBLE_EQ(bd1->psnr_high, 40.037);

  const std::vector<RatePoint> anchor2 = {{82472.76, 43.825},
                                          {26875.24, 41.404},
                                          {9487.76, 40.037},
                                          {4593.6, 38.615}};
  const std::vector<RatePoint> test2 = {{99896.96, 44.731}, {33952.04, 41.875}, {9787.8, 40.121}, {4469.0, 38.651}};
  const auto bd2 = bd_rate(anchor2, test2);
  ASSERT_TRUE(bd2.has_value());
  EXPECT_NEAR((bd2->ratio - 1) * 100, -4.4721820028, 1e-8);
  EXPECT_DOUBLE_EQ(bd2->psnr_low, 38.651);
  EXPECT_DOUBLE_EQ(bd2->psnr_high, 43.825);
}

TEST(BenchBdRate, UniformScaleIsExactAndSwappingInvertsIt) {
  std::vector<RatePoint> anchor, test;
  for (int q = 0; q < 6; ++q) {
    const double bytes = 1000.0 * std::pow(1.7, q) * (1 + 0.1 * (q % 2));
    anchor.push_back({bytes, 30.0 + 2.1 * q});
    test.push_back({bytes * 0.75, 30.0 + 2.1 * q});
  }
  EXPECT_NEAR(bd_rate(anchor, test)->ratio, 0.75, 1e-12);
  EXPECT_NEAR(bd_rate(test, anchor)->ratio, 1 / 0.75, 1e-12);
  EXPECT_NEAR(bd_rate(anchor, anchor)->ratio, 1.0, 1e-15);
}

TEST(BenchBdRate, WindowAveragesOverItsPartOfTheOverlapOnly) {
  // The test curve is 20 % smaller up to 36 dB and the same above: over 32-35 dB (whose
  // knots' PCHIP slopes see only the smaller part) the BD-rate is exactly -20 %, over the
  // whole overlap less.
  std::vector<RatePoint> anchor, test;
  for (int q = 0; q < 9; ++q) {
    const double psnr = 30.0 + q, bytes = 1000.0 * std::pow(1.5, q);
    anchor.push_back({bytes, psnr});
    test.push_back({psnr <= 36 ? bytes * 0.8 : bytes, psnr});
  }
  const auto low = bd_rate(anchor, test, 32, 35);
  ASSERT_TRUE(low.has_value());
  EXPECT_NEAR(low->ratio, 0.8, 1e-12);
  EXPECT_DOUBLE_EQ(low->psnr_low, 32);
  EXPECT_DOUBLE_EQ(low->psnr_high, 35);
  const auto whole = bd_rate(anchor, test);
  ASSERT_TRUE(whole.has_value());
  EXPECT_GT(whole->ratio, low->ratio + 0.02);
  EXPECT_DOUBLE_EQ(whole->psnr_low, 30);
  EXPECT_DOUBLE_EQ(whole->psnr_high, 38);
  // A window the curves do not reach: no BD-rate.
  EXPECT_FALSE(bd_rate(anchor, test, 40, 44).has_value());
}

TEST(BenchBdRate, PchipIntegralIsExactOnSegmentsAndMonotone) {
  // Two points: a straight line.
  EXPECT_NEAR(pchip_integral({0, 2}, {1, 5}, 0, 2), 6.0, 1e-12);
  EXPECT_NEAR(pchip_integral({0, 2}, {1, 5}, 0.5, 1.5), 3.0, 1e-12);
  // A flat stretch stays flat (no overshoot): the slope at the knot between rising and
  // flat data is zero, so the integral over the flat part is exact.
  EXPECT_NEAR(pchip_integral({0, 1, 2, 3}, {0, 1, 1, 1}, 1, 3), 2.0, 1e-12);
}

TEST(BenchBdRate, RefusesCurvesWithoutOverlapOrValidRates) {
  const std::vector<RatePoint> a = {{100, 30}, {200, 33}, {400, 36}};
  EXPECT_FALSE(bd_rate(a, {{100, 40}, {200, 44}}).has_value());
  EXPECT_FALSE(bd_rate(a, {{100, 31}}).has_value());
  EXPECT_FALSE(bd_rate(a, {{0, 31}, {100, 35}}).has_value());
  EXPECT_FALSE(bd_rate(a, {{100, 31}, {120, 31}}).has_value());
}

}  // namespace
}  // namespace svc::bench
