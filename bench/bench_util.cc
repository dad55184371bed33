// SPDX-License-Identifier: BSD-2-Clause
#include "bench_util.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <random>
#include <thread>

namespace svc::bench {

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

AccessStats summarize_access(std::vector<double> ms, const std::vector<int>& frames) {
  AccessStats stats;
  stats.samples = static_cast<int>(ms.size());
  if (ms.empty()) return stats;
  double sum = 0;
  for (double v : ms) sum += v;
  stats.mean_ms = sum / ms.size();
  std::sort(ms.begin(), ms.end());
  const size_t p99 = static_cast<size_t>(std::ceil(0.99 * ms.size())) - 1;
  stats.p99_ms = ms[std::min(p99, ms.size() - 1)];
  double frame_sum = 0;
  for (int f : frames) {
    frame_sum += f;
    stats.max_frames = std::max(stats.max_frames, f);
  }
  stats.mean_frames = frame_sum / frames.size();
  return stats;
}

std::vector<Pick> random_picks(size_t cells, int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<size_t> cell_dist(0, cells - 1);
  std::uniform_int_distribution<int> face_dist(0, kFaceCount - 1);
  std::vector<Pick> picks(std::max(0, count));
  for (Pick& p : picks) {
    p.cell = cell_dist(rng);
    p.face = kAllFaces[face_dist(rng)];
  }
  return picks;
}

std::array<int, 2> horizontal_axes(UpAxis up) {
  switch (up) {
    case UpAxis::kX: return {1, 2};
    case UpAxis::kZ: return {0, 1};
    default: return {0, 2};
  }
}

int& component(CellIndex& c, int axis) { return axis == 0 ? c.x : axis == 1 ? c.y : c.z; }

}  // namespace svc::bench
