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

std::string check_cdef_direction(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    uint8_t block[kSize * kSize];
    fill_window(random, block);  // the first 8 rows of 8 are used, stride 8
    if (random.uniform(0, 3) == 0) random.fill_with_extremes(block, 64);
    int32_t expected_variance = 0, actual_variance = 0;
    const int expected = reference.cdef_direction_8x8(block, 8, &expected_variance);
    const int actual = variant.cdef_direction_8x8(block, 8, &actual_variance);
    if (expected != actual || expected_variance != actual_variance) {
      return "direction " + std::to_string(expected) + " / " + std::to_string(actual) + ", variance " +
             std::to_string(expected_variance) + " / " + std::to_string(actual_variance);
    }
  }
  return {};
}

std::string check_cdef_filter(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  constexpr int kStride = 12;
  for (int n = 0; n < iterations; ++n) {
    const int size = random.uniform(0, 1) ? 8 : 4;
    uint8_t samples[kSize * kSize];
    fill_window(random, samples);
    uint16_t block[kStride * kStride];
    for (int i = 0; i < kStride * kStride; ++i) block[i] = samples[i];
    // Some sides outside the plane.
    const int edges = random.uniform(0, 15);
    for (int y = 0; y < kStride; ++y) {
      for (int x = 0; x < kStride; ++x) {
        const bool outside = ((edges & 1) && x < 2) || ((edges & 2) && y < 2) || ((edges & 4) && x >= size + 2) ||
                             ((edges & 8) && y >= size + 2);
        if (outside && random.uniform(0, 1)) block[y * kStride + x] = codec::dsp::kCdefUnavailable;
      }
    }
    constexpr int kSecondary[4] = {0, 1, 2, 4};
    const codec::dsp::CdefTaps taps{random.uniform(0, 15), kSecondary[random.uniform(0, 3)], random.uniform(0, 7),
                                    random.uniform(2, 6)};
    uint8_t expected[64] = {}, actual[64] = {};
    reference.cdef_filter_block(block + 2 * kStride + 2, kStride, expected, 8, size, taps);
    variant.cdef_filter_block(block + 2 * kStride + 2, kStride, actual, 8, size, taps);
    if (auto diff = first_difference(expected, actual, 64, 8); !diff.empty()) {
      return diff + " (size " + std::to_string(size) + ", primary " + std::to_string(taps.primary) +
             ", secondary " + std::to_string(taps.secondary) + ", direction " + std::to_string(taps.direction) +
             ", damping " + std::to_string(taps.damping) + ")";
    }
  }
  return {};
}

void bench_cdef_direction(const Tables& table, int iterations) {
  uint8_t block[64];
  for (int i = 0; i < 64; ++i) block[i] = static_cast<uint8_t>((i % 8) * 9 + (i / 8) * 5);
  int sum = 0;
  for (int n = 0; n < iterations; ++n) {
    int32_t variance;
    block[n & 63] ^= 1;
    sum += table.cdef_direction_8x8(block, 8, &variance);
  }
  bench_sink = sum;
}

void bench_cdef_filter(const Tables& table, int iterations) {
  uint16_t block[12 * 12];
  for (int i = 0; i < 144; ++i) block[i] = static_cast<uint16_t>(100 + (i * 7) % 9);
  uint8_t out[64];
  for (int n = 0; n < iterations; ++n) {
    table.cdef_filter_block(block + 26, 12, out, 8, 8, codec::dsp::CdefTaps{4, 2, n & 7, 4});
  }
  bench_sink = out[9];
}

}  // namespace

std::vector<Kernel> filter_kernels() {
  return {
      {"deblock_luma", [](const Tables& t) { return entry_of(t.deblock_luma); }, check_deblock_luma,
       bench_deblock_luma},
      {"deblock_chroma", [](const Tables& t) { return entry_of(t.deblock_chroma); }, check_deblock_chroma,
       bench_deblock_chroma},
      {"cdef_direction_8x8", [](const Tables& t) { return entry_of(t.cdef_direction_8x8); }, check_cdef_direction,
       bench_cdef_direction},
      {"cdef_filter_block", [](const Tables& t) { return entry_of(t.cdef_filter_block); }, check_cdef_filter,
       bench_cdef_filter},
  };
}

}  // namespace svc::checkkernels
