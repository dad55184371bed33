// SPDX-License-Identifier: BSD-2-Clause
// The bilinear sampling of cube padding's border: random runs of taps over planes of
// many widths, weights at the clamped extremes (0 and 16), blocks on the last row and
// column, and the bytes around each run's output.
#include <string>
#include <vector>

#include "checkkernels/harness.h"
#include "codec/common/cube_padding_map.h"

namespace svc::checkkernels {
namespace {

using codec::dsp::BilinearWeights;

constexpr int kGuard = 32;  // bytes compared on either side of a run's output

uint8_t axis_weight(Random& random) {
  switch (random.uniform(0, 3)) {
    case 0: return 0;
    case 1: return 16;
    default: return static_cast<uint8_t>(random.uniform(0, 16));
  }
}

BilinearWeights random_weights(Random& random) {
  const uint8_t x0 = axis_weight(random), y0 = axis_weight(random);
  return {x0, static_cast<uint8_t>(16 - x0), y0, static_cast<uint8_t>(16 - y0)};
}

// A block inside a width x height plane, often on its last row or column.
uint32_t random_index(Random& random, int width, int height) {
  const int x = random.uniform(0, 3) == 0 ? width - 2 : random.uniform(0, width - 2);
  const int y = random.uniform(0, 3) == 0 ? height - 2 : random.uniform(0, height - 2);
  return static_cast<uint32_t>(y * width + x);
}

struct Run {
  std::vector<uint8_t> plane;
  int width;
  std::vector<uint32_t> index;
  std::vector<BilinearWeights> weights;
};

Run random_run(Random& random) {
  Run run;
  run.width = random.uniform(2, 300);
  const int height = random.uniform(2, 40), count = random.uniform(0, 80);
  run.plane.resize(static_cast<size_t>(run.width) * height);
  random.fill_with_extremes(run.plane.data(), run.plane.size());
  for (int k = 0; k < count; ++k) {
    run.index.push_back(random_index(random, run.width, height));
    run.weights.push_back(random_weights(random));
  }
  return run;
}

std::vector<uint8_t> sample(const Tables& table, const Run& run) {
  const int count = static_cast<int>(run.index.size());
  std::vector<uint8_t> out(count + 2 * kGuard, 0x5A);
  table.pad_sample_run(run.plane.data(), run.width, run.index.data(), run.weights.data(), count,
                       out.data() + kGuard);
  return out;
}

std::string check_pad_sample_run(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    const Run run = random_run(random);
    const std::vector<uint8_t> expected = sample(reference, run), got = sample(variant, run);
    const std::string difference = first_difference(expected.data(), got.data(), expected.size());
    if (!difference.empty()) {
      return difference + " (output from index " + std::to_string(kGuard) + ", " +
             std::to_string(run.index.size()) + " samples, plane width " + std::to_string(run.width) + ")";
    }
  }
  return {};
}

// The border map of a 256-sample face with a 64-sample border, run after run, each run
// read from one 256 x 256 plane.
void bench_pad_sample_run(const Tables& table, int iterations) {
  static const codec::cube_padding_internal::BorderMap map =
      codec::cube_padding_internal::build_border_map(0, 256, 64);
  std::vector<uint8_t> plane(256 * 256);
  for (size_t i = 0; i < plane.size(); ++i) plane[i] = static_cast<uint8_t>(i * 7 + i / 256);
  std::vector<uint8_t> out(384 * 384);
  std::vector<size_t> first_tap = {0};
  for (const auto& run : map.runs) first_tap.push_back(first_tap.back() + run.count);
  for (int n = 0; n < iterations; ++n) {
    const size_t r = static_cast<size_t>(n) % map.runs.size();
    table.pad_sample_run(plane.data(), 256, map.indices.data() + first_tap[r], map.weights.data() + first_tap[r],
                         static_cast<int>(map.runs[r].count), out.data() + map.runs[r].offset);
  }
  bench_sink = out[100];
}

}  // namespace

std::vector<Kernel> pad_kernels() {
  return {
      {"pad_sample_run", [](const Tables& t) { return entry_of(t.pad_sample_run); }, check_pad_sample_run,
       bench_pad_sample_run},
  };
}

}  // namespace svc::checkkernels
