// The in-loop filter kernels: deblocking of an edge segment, both orientations.
#include <string>
#include <vector>

#include "checkkernels/harness.h"

namespace svc::checkkernels {
namespace {

constexpr int kSize = 16;  // a 16x16 window; the edge runs between columns (rows) 7 and 8

// Samples that reach every decision: flat sides with a step (strong filter), gentle
// ramps (normal filter, one or both outer samples), noise (no filter) and extremes.
void fill_window(Random& random, uint8_t* window) {
  const int kind = random.uniform(0, 4);
  const int base = random.uniform(0, 255), step = random.uniform(-40, 40), slope = random.uniform(-3, 3);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      int v = base + (x >= 8 ? step : 0) + slope * x + (kind == 1 ? random.uniform(-2, 2) : 0);
      if (kind == 2) v = random.uniform(0, 255);
      window[y * kSize + x] = static_cast<uint8_t>(std::clamp(v, 0, 255));
    }
  }
  if (kind == 3) random.fill_with_extremes(window, kSize * kSize);
}

template <typename Run>
std::string check_segments(Random& random, int iterations, Run run) {
  for (int n = 0; n < iterations; ++n) {
    uint8_t input[kSize * kSize];
    fill_window(random, input);
    const bool vertical = random.uniform(0, 1) != 0;
    const int beta = random.uniform(0, 3) == 0 ? (random.uniform(0, 1) ? 0 : 64) : random.uniform(0, 64);
    const int tc = random.uniform(0, 3) == 0 ? (random.uniform(0, 1) ? 0 : 24) : random.uniform(0, 24);
    const int offset = random.uniform(0, 12);  // first line of the segment
    std::vector<uint8_t> expected(input, input + kSize * kSize), actual = expected;
    // The edge between x (or y) 7 and 8; lines run along the other axis.
    const ptrdiff_t across = vertical ? 1 : kSize, along = vertical ? kSize : 1;
    const ptrdiff_t q0 = 8 * across + offset * along;
    run(true, expected.data() + q0, across, along, beta, tc);
    run(false, actual.data() + q0, across, along, beta, tc);
    if (auto diff = first_difference(expected.data(), actual.data(), kSize * kSize, kSize); !diff.empty()) {
      return diff + " (" + (vertical ? "vertical" : "horizontal") + " edge, beta " + std::to_string(beta) +
             ", tc " + std::to_string(tc) + ")";
    }
  }
  return {};
}

std::string check_deblock_luma(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  return check_segments(random, iterations,
                        [&](bool ref, uint8_t* p, ptrdiff_t across, ptrdiff_t along, int beta, int tc) {
                          (ref ? reference : variant).deblock_luma(p, across, along, beta, tc);
                        });
}

std::string check_deblock_chroma(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  return check_segments(random, iterations,
                        [&](bool ref, uint8_t* p, ptrdiff_t across, ptrdiff_t along, int, int tc) {
                          (ref ? reference : variant).deblock_chroma(p, across, along, tc);
                        });
}

void bench_deblock_luma(const Tables& table, int iterations) {
  uint8_t window[kSize * kSize];
  for (int i = 0; i < kSize * kSize; ++i) window[i] = static_cast<uint8_t>(100 + (i % kSize >= 8 ? 6 : 0));
  for (int n = 0; n < iterations; ++n) {
    const bool vertical = n & 1;
    table.deblock_luma(window + (vertical ? 8 : 8 * kSize), vertical ? 1 : kSize, vertical ? kSize : 1, 40, 4);
  }
  bench_sink = window[7];
}

void bench_deblock_chroma(const Tables& table, int iterations) {
  uint8_t window[kSize * kSize];
  for (int i = 0; i < kSize * kSize; ++i) window[i] = static_cast<uint8_t>(100 + (i % kSize >= 8 ? 6 : 0));
  for (int n = 0; n < iterations; ++n) {
    const bool vertical = n & 1;
    table.deblock_chroma(window + (vertical ? 8 : 8 * kSize), vertical ? 1 : kSize, vertical ? kSize : 1, 4);
  }
  bench_sink = window[7];
}

}  // namespace

std::vector<Kernel> filter_kernels() {
  return {
      {"deblock_luma", [](const Tables& t) { return entry_of(t.deblock_luma); }, check_deblock_luma,
       bench_deblock_luma},
      {"deblock_chroma", [](const Tables& t) { return entry_of(t.deblock_chroma); }, check_deblock_chroma,
       bench_deblock_chroma},
  };
}

}  // namespace svc::checkkernels
