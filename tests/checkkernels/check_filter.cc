// SPDX-License-Identifier: BSD-2-Clause
// The in-loop filter kernels: deblocking of an edge's segments, both orientations; CDEF.
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

// Runs of segments along one edge: each segment its own content (so the strong, normal
// and no-filter decisions mix within a call), its own tc (0 often), 1 to 11 segments
// (pairs, groups of four and odd ones left over), both orientations, odd strides.
constexpr int kEdgeWindow = 56;  // lines along the edge at most 48, samples across 16

// Fills the 4 lines of one segment, p3..q3 around the edge at q0, with one kind of
// content: a step on flat sides (strong), gentle ramps with noise (normal), noise (no
// filter), a small step (strong at small tc) or extremes (saturating the clips).
void fill_segment(Random& random, uint8_t* q0, ptrdiff_t across, ptrdiff_t along) {
  const int kind = random.uniform(0, 4), extremes = random.uniform(0, 3);
  const int base = random.uniform(0, 255), slope = random.uniform(-3, 3);
  const int step = kind == 3 ? random.uniform(-3, 3) : random.uniform(-40, 40);
  for (int line = 0; line < 4; ++line) {
    for (int k = -4; k < 4; ++k) {
      int v = base + (k >= 0 ? step : 0) + slope * k + (kind == 1 ? random.uniform(-2, 2) : 0);
      if (kind == 2) v = random.uniform(0, 255);
      if (kind == 4)
        v = extremes == 0   ? 0
            : extremes == 1 ? 255
            : extremes == 2 ? (k < 0 ? 0 : 255)
                            : 255 * random.uniform(0, 1);
      q0[line * along + k * across] = static_cast<uint8_t>(std::clamp(v, 0, 255));
    }
  }
}

struct EdgeCase {
  std::vector<uint8_t> window, tc;
  ptrdiff_t q0 = 0, across = 0, along = 0;
  int beta = 0;
  std::string describe() const {
    std::string text = across == 1 ? "vertical" : "horizontal";
    text += " edge, beta " + std::to_string(beta) + ", tc";
    for (uint8_t t : tc) text.append(" ").append(std::to_string(t));
    return text;
  }
};

EdgeCase random_edge(Random& random) {
  EdgeCase e;
  const int stride = random.uniform(48, kEdgeWindow);
  e.window.resize(static_cast<size_t>(stride) * kEdgeWindow);
  random.fill(e.window.data(), e.window.size());
  const bool vertical = random.uniform(0, 1) != 0;
  e.across = vertical ? 1 : stride;
  e.along = vertical ? stride : 1;
  e.q0 = 8 * e.across + random.uniform(0, 3) * e.along;  // the edge between 7 and 8 across
  e.beta = random.uniform(0, 3) == 0 ? (random.uniform(0, 1) ? 0 : 64) : random.uniform(0, 64);
  e.tc.resize(static_cast<size_t>(random.uniform(1, 11)));
  const bool same_tc = random.uniform(0, 3) == 0;
  for (size_t s = 0; s < e.tc.size(); ++s) {
    const int pick = random.uniform(0, 4);
    e.tc[s] = static_cast<uint8_t>(s > 0 && same_tc ? e.tc[0]
                                   : pick == 0      ? 0
                                   : pick == 1      ? 24
                                                    : random.uniform(1, 24));
    fill_segment(random, e.window.data() + e.q0 + static_cast<ptrdiff_t>(4 * s) * e.along, e.across, e.along);
  }
  return e;
}

template <typename Run>
std::string check_edges(Random& random, int iterations, Run run) {
  for (int n = 0; n < iterations; ++n) {
    EdgeCase e = random_edge(random);
    std::vector<uint8_t> expected = e.window, actual = e.window;
    run(true, expected.data() + e.q0, e);
    run(false, actual.data() + e.q0, e);
    const size_t stride = e.window.size() / kEdgeWindow;
    if (auto diff = first_difference(expected.data(), actual.data(), e.window.size(), stride); !diff.empty()) {
      return diff + " (" + e.describe() + ")";
    }
  }
  return {};
}

std::string check_deblock_luma(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  return check_edges(random, iterations, [&](bool ref, uint8_t* p, const EdgeCase& e) {
    (ref ? reference : variant)
        .deblock_luma(p, e.across, e.along, static_cast<int>(e.tc.size()), e.beta, e.tc.data());
  });
}

std::string check_deblock_chroma(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  return check_edges(random, iterations, [&](bool ref, uint8_t* p, const EdgeCase& e) {
    (ref ? reference : variant).deblock_chroma(p, e.across, e.along, static_cast<int>(e.tc.size()), e.tc.data());
  });
}

// A 64-sample edge (16 segments, tc 4, beta 40) across the middle of a 64x64 plane,
// vertical and horizontal in turn: segments with a step on flat sides (strong), ramps
// (normal) and noise (none).
struct BenchEdges {
  uint8_t vertical[64 * 64], horizontal[64 * 64];  // the same content, transposed
  uint8_t tc[16];
  BenchEdges() {
    for (int line = 0; line < 64; ++line) {
      for (int k = 0; k < 64; ++k) {
        const int kind = line / 4 % 3, step = k >= 32 ? 6 : 0;
        const int v = kind == 0 ? 100 + step : kind == 1 ? 60 + 2 * k + step : (k * 37 + line * 91) % 256;
        vertical[line * 64 + k] = horizontal[k * 64 + line] = static_cast<uint8_t>(v);
      }
    }
    std::fill(tc, tc + 16, uint8_t{4});
  }
};

void bench_deblock_luma(const Tables& table, int iterations) {
  BenchEdges edges;
  for (int n = 0; n < iterations; ++n) {
    if (n & 1) {
      table.deblock_luma(edges.vertical + 32, 1, 64, 16, 40, edges.tc);
    } else {
      table.deblock_luma(edges.horizontal + 32 * 64, 64, 1, 16, 40, edges.tc);
    }
  }
  bench_sink = edges.vertical[31] + edges.horizontal[31 * 64];
}

void bench_deblock_chroma(const Tables& table, int iterations) {
  BenchEdges edges;
  for (int n = 0; n < iterations; ++n) {
    if (n & 1) {
      table.deblock_chroma(edges.vertical + 32, 1, 64, 16, edges.tc);
    } else {
      table.deblock_chroma(edges.horizontal + 32 * 64, 64, 1, 16, edges.tc);
    }
  }
  bench_sink = edges.vertical[31] + edges.horizontal[31 * 64];
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
    // Primary strength 0 a quarter of the time, like secondary 0: the variants skip the
    // unused taps and the clamp then.
    const int primary = random.uniform(0, 3) == 0 ? 0 : random.uniform(1, 15);
    const codec::dsp::CdefTaps taps{primary, kSecondary[random.uniform(0, 3)], random.uniform(0, 7),
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
