// SPDX-License-Identifier: BSD-2-Clause
// Random transform coefficients for the inverse-transform tests: dense, sparse, or a DC
// at the coefficient limits, so that clamps and rounding are exercised.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "codec/common/dct.h"

namespace svc::testing {

inline std::vector<int16_t> random_coefficients(std::mt19937& rng, int area) {
  std::vector<int16_t> coefficients(static_cast<size_t>(area), 0);
  const int pattern = static_cast<int>(rng() % 3);
  for (int i = 0; i < area; ++i) {
    if (pattern == 0 || (pattern == 1 && rng() % 8 == 0)) {
      coefficients[static_cast<size_t>(i)] = static_cast<int16_t>(static_cast<int>(rng() % 4096) - 2048);
    }
  }
  if (pattern == 2)
    coefficients[0] = static_cast<int16_t>(rng() % 2 ? codec::kMaxCoefficient : codec::kMinCoefficient);
  return coefficients;
}

}  // namespace svc::testing
