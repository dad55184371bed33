// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "codec/common/dct.h"
#include "codec/common/quant.h"
#include "codec/encoder/forward_transform.h"

namespace svc::codec {
namespace {

TEST(CodecDct, FastForwardMatchesReference) {
  std::mt19937 rng(1);
  double max_error = 0;
  for (int n = 0; n < 2000; ++n) {
    float samples[64], fast[64];
    double samples_d[64], reference[64];
    for (int i = 0; i < 64; ++i) {
      samples[i] = static_cast<float>(static_cast<int>(rng() % 512) - 256);
      samples_d[i] = samples[i];
    }
    forward_dct_8x8(samples, fast);
    forward_dct_8x8_reference(samples_d, reference);
    for (int i = 0; i < 64; ++i) max_error = std::max(max_error, std::fabs(fast[i] - reference[i]));
  }
  EXPECT_LT(max_error, 0.01);
}

TEST(CodecDct, DcIsEightTimesTheMean) {
  double samples[64], coefficients[64];
  for (double& s : samples) s = 10;
  forward_dct_8x8_reference(samples, coefficients);
  EXPECT_NEAR(coefficients[0], 80, 1e-9);
  for (int i = 1; i < 64; ++i) EXPECT_NEAR(coefficients[i], 0, 1e-9);
  int16_t dc_only[64] = {80};
  int16_t out[64];
  inverse_dct_8x8(dc_only, out);
  for (int i = 0; i < 64; ++i) EXPECT_EQ(out[i], 10);
}

TEST(CodecDct, ReferencePairIsAnExactInverse) {
  std::mt19937 rng(2);
  double samples[64], coefficients[64], back[64];
  for (double& s : samples) s = static_cast<double>(rng() % 1000) / 7.0;
  forward_dct_8x8_reference(samples, coefficients);
  inverse_dct_8x8_reference(coefficients, back);
  for (int i = 0; i < 64; ++i) EXPECT_NEAR(back[i], samples[i], 1e-9);
}

// IEEE 1180-1990 procedure: random pixel blocks in [-low, high], exact forward DCT
// rounded to integers and clamped to 12 bits, then the integer inverse is compared with
// the exact inverse (both clipped to [-256, 255]).
void check_ieee1180(int low, int high, int sign, uint32_t seed, int blocks) {
  std::mt19937 rng(seed);
  double sum_error[64] = {}, sum_squared[64] = {};
  int peak = 0;
  for (int n = 0; n < blocks; ++n) {
    double samples[64], coefficients[64], exact[64];
    int16_t integer_coefficients[64], integer_out[64];
    for (int i = 0; i < 64; ++i) {
      samples[i] = sign * (static_cast<int>(rng() % static_cast<uint32_t>(low + high + 1)) - low);
    }
    forward_dct_8x8_reference(samples, coefficients);
    double rounded[64];
    for (int i = 0; i < 64; ++i) {
      const int c = std::clamp(static_cast<int>(std::lround(coefficients[i])), kMinCoefficient, kMaxCoefficient);
      integer_coefficients[i] = static_cast<int16_t>(c);
      rounded[i] = c;
    }
    inverse_dct_8x8_reference(rounded, exact);
    inverse_dct_8x8(integer_coefficients, integer_out);
    for (int i = 0; i < 64; ++i) {
      const int want = std::clamp(static_cast<int>(std::lround(exact[i])), -256, 255);
      const int got = std::clamp<int>(integer_out[i], -256, 255);
      const int error = got - want;
      peak = std::max(peak, std::abs(error));
      sum_error[i] += error;
      sum_squared[i] += error * error;
    }
  }
  double total_error = 0, total_squared = 0;
  for (int i = 0; i < 64; ++i) {
    EXPECT_LE(std::fabs(sum_error[i]) / blocks, 0.015) << "position " << i;
    EXPECT_LE(sum_squared[i] / blocks, 0.06) << "position " << i;
    total_error += sum_error[i];
    total_squared += sum_squared[i];
  }
  std::printf("[ ieee1180 ] range -%d..%d sign %+d: peak %d, mean error %.5f, mse %.5f\n", low, high, sign, peak,
              total_error / (64.0 * blocks), total_squared / (64.0 * blocks));
  EXPECT_LE(peak, 1);
  EXPECT_LE(std::fabs(total_error) / (64.0 * blocks), 0.0015);
  EXPECT_LE(total_squared / (64.0 * blocks), 0.02);
}

TEST(CodecDct, IntegerInverseMeetsIeee1180) {
  for (int sign : {1, -1}) {
    check_ieee1180(256, 255, sign, 11, 10000);
    check_ieee1180(5, 5, sign, 12, 10000);
    check_ieee1180(300, 300, sign, 13, 10000);
  }
}

TEST(CodecDct, IntegerInverseMatchesPlainIntegerReferenceBitExactly) {
  std::mt19937 rng(3);
  for (int n = 0; n < 20000; ++n) {
    int16_t coefficients[64] = {};
    // Mix of DC-only, sparse and dense blocks, including the extreme values.
    const int kind = n % 4;
    const int count = kind == 0 ? 1 : (kind == 1 ? 3 : (kind == 2 ? 20 : 64));
    for (int k = 0; k < count; ++k) {
      const int position = kind == 0 ? 0 : static_cast<int>(rng() % 64);
      const int value = n % 50 == 0 ? (rng() & 1 ? kMaxCoefficient : kMinCoefficient)
                                    : static_cast<int>(rng() % 4096) - 2048;
      coefficients[position] = static_cast<int16_t>(value);
    }
    int16_t fast[64], plain[64];
    inverse_dct_8x8(coefficients, fast);
    inverse_dct_8x8_integer_reference(coefficients, plain);
    for (int i = 0; i < 64; ++i) ASSERT_EQ(fast[i], plain[i]) << "block " << n << " position " << i;
  }
}

TEST(CodecDct, ZeroBlockInvertsToZero) {
  int16_t zero[64] = {}, out[64];
  inverse_dct_8x8(zero, out);
  for (int v : out) EXPECT_EQ(v, 0);
}

}  // namespace
}  // namespace svc::codec
