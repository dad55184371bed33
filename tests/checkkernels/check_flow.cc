// SPDX-License-Identifier: BSD-2-Clause
// The encoder's flow kernels against their references: flow rows with depths that are
// NaN, infinite, huge, negative, at the far plane or just in front of the reference
// camera; half-pel keys on rounding boundaries (exact halves) and at the limit; run-end
// masks over keys that differ in any byte. Row widths 1 to 40, the face widths, odd ones.
#include <algorithm>
#include <cmath>
#include <limits>

#include "checkkernels/harness.h"

namespace svc::checkkernels {
namespace {

constexpr int kFaceWidths[] = {16, 64, 128, 256, 512, 1024};

int random_width(Random& random, int n) {
  if (n < 40) return n + 1;
  if (random.uniform(0, 2) == 0) return kFaceWidths[random.uniform(0, 5)];
  return random.uniform(1, 550) * 2 - 1;  // odd
}

double random_double(Random& random, double lo, double hi) {
  // Two draws, so that the low bits of the mantissa are not all zero.
  return static_cast<double>(random.uniform_float(static_cast<float>(lo), static_cast<float>(hi))) +
         static_cast<double>(random.uniform_float(0.0f, 1.0f)) * 1e-9 * (hi - lo);
}

float special_float(Random& random) {
  constexpr float values[] = {std::numeric_limits<float>::quiet_NaN(),
                              -std::numeric_limits<float>::quiet_NaN(),
                              std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(),
                              std::numeric_limits<float>::max(),
                              -std::numeric_limits<float>::max(),
                              1e30f,
                              -1e30f,
                              0.0f,
                              -0.0f,
                              1e-40f,
                              -1e-40f};
  return values[random.uniform(0, static_cast<int>(std::size(values)) - 1)];
}

// A depth of every kind compute_flow meets, and some it should never.
float random_depth(Random& random, const FlowRow& row, int i) {
  switch (random.uniform(0, 7)) {
    case 0: return special_float(random);
    case 1: return static_cast<float>(row.far_plane);  // exactly at the far plane: background
    case 2: return -random.uniform_float(0.0f, 100.0f);
    case 3: {
      // pz right at the in-front limit (-1e-9), give or take a few ulps of z.
      const double dir_z = row.column_z[i] + row.row_z;
      const float z = static_cast<float>((-1e-9 - row.shift_z) / dir_z);
      return std::nextafter(z, random.uniform(0, 1) ? 1e30f : -1e30f);
    }
    default: return random.uniform_float(0.0f, static_cast<float>(row.far_plane) * 1.5f);
  }
}

std::string flow_input(const std::string& diff, const FlowRow& row, size_t offset) {
  return diff + " (count " + std::to_string(row.count) + ", row " + std::to_string(row.row) + ", offset " +
         std::to_string(offset) + ")";
}

std::string check_flow_row(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations + 40; ++n) {
    const int count = random_width(random, n);
    const size_t offset = static_cast<size_t>(random.uniform(0, 3)), size = static_cast<size_t>(count) + 8;
    std::vector<double> columns(3 * size);
    for (double& c : columns) c = random_double(random, -2.0, 2.0);
    FlowRow row{};
    row.column_x = columns.data() + offset;
    row.column_y = row.column_x + size;
    row.column_z = row.column_y + size;
    row.row_x = random_double(random, -1.0, 1.0);
    row.row_y = random_double(random, -1.0, 1.0);
    row.row_z = random_double(random, -3.0, 1.0);
    const bool moves = random.uniform(0, 3) != 0;
    row.shift_x = moves ? random_double(random, -5.0, 5.0) : 0.0;
    row.shift_y = moves ? random_double(random, -5.0, 5.0) : 0.0;
    row.shift_z = moves ? random_double(random, -5.0, 5.0) : 0.0;
    // Sometimes a projection so steep that the flow overflows to infinity.
    row.p00 = random.uniform(0, 9) == 0 ? 1e300 : random_double(random, 0.2, 4.0);
    row.p11 = random.uniform(0, 9) == 0 ? 1e300 : random_double(random, 0.2, 4.0);
    row.p02 = random_double(random, -1.0, 1.0);
    row.p12 = random_double(random, -1.0, 1.0);
    row.width = count;
    row.height = random.uniform(1, 2048);
    // Sometimes no far plane (then only the depth's own finiteness makes it background),
    // or a NaN one (everything is background).
    const double far_planes[] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()};
    row.far_plane = random.uniform(0, 9) == 0 ? far_planes[random.uniform(0, 1)]
                                              : random_double(random, 0.5, 1000.0);
    row.row = random.uniform(0, static_cast<int>(row.height) - 1);
    row.count = count;
    std::vector<float> depth(size);
    for (int i = 0; i < count; ++i) depth[offset + static_cast<size_t>(i)] = random_depth(random, row, i);
    // Outputs with guard values after the row: a variant must not write past it.
    std::vector<float> dx[2], dy[2];
    std::vector<uint8_t> valid[2];
    const Tables* tables[2] = {&reference, &variant};
    for (int t = 0; t < 2; ++t) {
      dx[t].assign(size, -7.0f);
      dy[t].assign(size, -7.0f);
      valid[t].assign(size, 0xA5);
      tables[t]->flow.flow_row(row, depth.data() + offset, dx[t].data() + offset, dy[t].data() + offset,
                               valid[t].data() + offset);
    }
    if (auto diff = first_difference(dx[0].data(), dx[1].data(), size); !diff.empty())
      return flow_input("dx: " + diff, row, offset);
    if (auto diff = first_difference(dy[0].data(), dy[1].data(), size); !diff.empty())
      return flow_input("dy: " + diff, row, offset);
    if (auto diff = first_difference(valid[0].data(), valid[1].data(), size); !diff.empty())
      return flow_input("valid: " + diff, row, offset);
  }
  return {};
}

// A flow component for keys under `limit`: random, on a quarter pel (twice it is an
// exact half: the rounding boundary), at the limit's edge, or special.
float random_component(Random& random, int limit) {
  const float sign = random.uniform(0, 1) ? 1.0f : -1.0f;
  switch (random.uniform(0, 5)) {
    case 0: return special_float(random);
    case 1: return sign * static_cast<float>(random.uniform(0, 4 * limit + 8)) * 0.25f;
    case 2: {
      const float edge = (static_cast<float>(limit) + static_cast<float>(random.uniform(-4, 4)) * 0.25f) * 0.5f;
      return sign * (random.uniform(0, 1) ? edge : std::nextafter(edge, random.uniform(0, 1) ? 1e30f : 0.0f));
    }
    case 3:
      return sign * std::nextafter(static_cast<float>(random.uniform(0, 200)) + 0.25f,
                                   random.uniform(0, 1) ? 1e30f : 0.0f);
    default: return random.uniform_float(-0.6f * static_cast<float>(limit), 0.6f * static_cast<float>(limit));
  }
}

std::string check_quarter_pel_keys(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  constexpr int32_t kNoKey = std::numeric_limits<int32_t>::min();
  for (int n = 0; n < iterations + 64; ++n) {
    const size_t count = n < 64 ? static_cast<size_t>(n)
                                : static_cast<size_t>(random.uniform(0, 3) == 0 ? 16 * random_width(random, n)
                                                                                : random.uniform(1, 700));
    int limit = 0;
    switch (random.uniform(0, 2)) {
      case 0: limit = 32767; break;
      case 1: limit = 2 * std::max(random_width(random, n), random.uniform(1, 1100)); break;  // as the encoder
      default: limit = random.uniform(1, 32767);
    }
    const size_t offset = static_cast<size_t>(random.uniform(0, 3)), size = count + 8;
    std::vector<float> dx(size), dy(size);
    std::vector<uint8_t> valid(size);
    for (size_t i = offset; i < offset + count; ++i) {
      dx[i] = random_component(random, limit);
      dy[i] = random_component(random, limit);
      const int v = random.uniform(0, 5);
      valid[i] = static_cast<uint8_t>(v == 0 ? 0 : v == 1 ? random.byte() : 1);
    }
    std::vector<int32_t> expected(size, 0x5a5a5a5a), actual(size, 0x5a5a5a5a);
    reference.flow.quarter_pel_keys(dx.data() + offset, dy.data() + offset, valid.data() + offset, count, limit,
                                    kNoKey, expected.data() + offset);
    variant.flow.quarter_pel_keys(dx.data() + offset, dy.data() + offset, valid.data() + offset, count, limit,
                                  kNoKey, actual.data() + offset);
    if (auto diff = first_difference(expected.data(), actual.data(), size); !diff.empty()) {
      const size_t at =
          std::min(size - 1,
                   static_cast<size_t>(std::mismatch(expected.begin(), expected.end(), actual.begin()).first -
                                       expected.begin()));
      return diff + " (count " + std::to_string(count) + ", limit " + std::to_string(limit) + ", offset " +
             std::to_string(offset) + ", dx " + to_text(dx[at]) + ", dy " + to_text(dy[at]) + ", valid " +
             to_text(valid[at]) + ")";
    }
  }
  return {};
}

std::string check_run_ends_16(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < 20 * iterations; ++n) {
    // Keys that differ in one byte or the sign only, so that a narrower compare fails.
    const int32_t base = random.uniform(std::numeric_limits<int32_t>::min(), std::numeric_limits<int32_t>::max());
    const int32_t alphabet[] = {base,
                                base ^ 1,
                                base ^ 0x100,
                                base ^ 0x10000,
                                base ^ 0x1000000,
                                static_cast<int32_t>(static_cast<uint32_t>(base) ^ 0x80000000u),
                                std::numeric_limits<int32_t>::min()};
    const int repeat = random.uniform(0, 9);  // in tenths: how often a key repeats its left neighbour
    int32_t keys[16 + 4];
    for (int i = 0; i < 20; ++i) {
      keys[i] = i > 0 && random.uniform(0, 9) < repeat ? keys[i - 1] : alphabet[random.uniform(0, 6)];
    }
    const int32_t* row = keys + random.uniform(0, 4);  // unaligned
    const unsigned expected = reference.flow.run_ends_16(row), actual = variant.flow.run_ends_16(row);
    if (expected != actual) {
      std::string input;
      for (int i = 0; i < 16; ++i) input.append(i ? " " : "").append(std::to_string(row[i]));
      return "mask: reference " + std::to_string(expected) + ", variant " + std::to_string(actual) + " (keys " +
             input + ")";
    }
  }
  return {};
}

constexpr int kBenchWidth = 512;  // a face row

void bench_flow_row(const Tables& table, int iterations) {
  std::vector<double> columns(3 * kBenchWidth);
  for (int i = 0; i < kBenchWidth; ++i) {
    const double a = (i + 0.5) / kBenchWidth * 2.0 - 1.0;
    columns[static_cast<size_t>(i)] = a * 0.99;
    columns[static_cast<size_t>(kBenchWidth + i)] = a * 0.01;
    columns[static_cast<size_t>(2 * kBenchWidth + i)] = a * 0.1;
  }
  const FlowRow row{columns.data(),
                    columns.data() + kBenchWidth,
                    columns.data() + 2 * kBenchWidth,
                    0.1,
                    0.3,
                    -1.0,
                    0.2,
                    0.0,
                    0.1,
                    1.0,
                    0.0,
                    1.0,
                    0.0,
                    kBenchWidth,
                    kBenchWidth,
                    100.0,
                    200,
                    kBenchWidth};
  std::vector<float> depth(kBenchWidth), dx(kBenchWidth), dy(kBenchWidth);
  std::vector<uint8_t> valid(kBenchWidth);
  for (int i = 0; i < kBenchWidth; ++i) depth[static_cast<size_t>(i)] = i % 64 == 0 ? 1e9f : 5.0f + 0.01f * i;
  for (int n = 0; n < iterations; ++n) table.flow.flow_row(row, depth.data(), dx.data(), dy.data(), valid.data());
  bench_sink = valid[7] + static_cast<int>(dx[7]);
}

void bench_quarter_pel_keys(const Tables& table, int iterations) {
  std::vector<float> dx(kBenchWidth), dy(kBenchWidth);
  std::vector<uint8_t> valid(kBenchWidth, 1);
  for (int i = 0; i < kBenchWidth; ++i) {
    dx[static_cast<size_t>(i)] = 3.1f + 0.002f * i;
    dy[static_cast<size_t>(i)] = -1.4f - 0.001f * i;
  }
  std::vector<int32_t> keys(kBenchWidth);
  for (int n = 0; n < iterations; ++n) {
    table.flow.quarter_pel_keys(dx.data(), dy.data(), valid.data(), kBenchWidth, 1024, -1, keys.data());
  }
  bench_sink = keys[7];
}

void bench_run_ends_16(const Tables& table, int iterations) {
  int32_t keys[64];
  for (int i = 0; i < 64; ++i) keys[i] = i / 5;
  unsigned sum = 0;
  for (int n = 0; n < iterations; ++n) sum += table.flow.run_ends_16(keys + 16 * (n & 3));
  bench_sink = static_cast<int>(sum);
}

}  // namespace

std::vector<Kernel> flow_kernels() {
  return {
      {"flow_row", [](const Tables& t) { return entry_of(t.flow.flow_row); }, check_flow_row, bench_flow_row},
      {"quarter_pel_keys", [](const Tables& t) { return entry_of(t.flow.quarter_pel_keys); },
       check_quarter_pel_keys, bench_quarter_pel_keys},
      {"run_ends_16", [](const Tables& t) { return entry_of(t.flow.run_ends_16); }, check_run_ends_16,
       bench_run_ends_16},
  };
}

}  // namespace svc::checkkernels
