// SPDX-License-Identifier: BSD-2-Clause
// Small pieces shared by the parts of `svc bench`: timing, a worker pool, random picks
// and access statistics.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <vector>

#include "common/parallel.h"
#include "database/database.h"
#include "svc/status.h"
#include "svc/types.h"
#include "svc_bench.h"

namespace svc::bench {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start);

AccessStats summarize_access(std::vector<double> ms, const std::vector<int>& frames);

struct Pick {
  size_t cell = 0;  // ordinal in the manifest
  Face face = Face::kPX;
};

std::vector<Pick> random_picks(size_t cells, int count, uint32_t seed);

// The two grid axes of a layer: subsampling thins these and keeps every layer.
std::array<int, 2> horizontal_axes(UpAxis up);

int& component(CellIndex& c, int axis);

}  // namespace svc::bench
