// SPDX-License-Identifier: BSD-2-Clause
// The median the benchmarks report of repeated timings: on a shared, noisy machine it
// is steadier than a single pass or the mean.
#pragma once

#include <algorithm>
#include <vector>

namespace svc::bench {

// Median of `values` (the mean of the middle two for an even count); 0 when empty.
inline double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t middle = values.size() / 2;
  return values.size() % 2 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
}

}  // namespace svc::bench
