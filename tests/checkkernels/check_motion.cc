// Motion-compensation and warp kernels against their references: every block size the
// codec uses (16x16 luma, 8x8 chroma) and others up to 64, each half-pel phase, odd
// strides, unaligned pointers, and the bytes around each output block.
#include <algorithm>
#include <array>

#include "checkkernels/harness.h"

namespace svc::checkkernels {
namespace {

using codec::dsp::WarpRow;

constexpr std::array<int, 13> kBlockWidths = {16, 8, 1, 2, 3, 4, 7, 9, 15, 17, 24, 32, 64};

std::string describe(const std::string& diff, int width, int height, int fx, int fy, ptrdiff_t stride) {
  return diff + " (block " + std::to_string(width) + "x" + std::to_string(height) + ", fx " + std::to_string(fx) +
         ", fy " + std::to_string(fy) + ", stride " + std::to_string(stride) + ")";
}

std::string check_put_half_pel(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    const int width = kBlockWidths[static_cast<size_t>(n) % kBlockWidths.size()];
    const int height = n % 3 == 0 ? width : random.uniform(1, 64);
    const int fx = n & 1, fy = (n >> 1) & 1;
    const ptrdiff_t stride = width + 1 + random.uniform(0, 21), out_stride = width + random.uniform(0, 9);
    const size_t offset = static_cast<size_t>(random.uniform(0, 15));
    Buffer window(static_cast<size_t>(stride) * (height + 1) + 16);
    random.fill_with_extremes(window.at(offset), static_cast<size_t>(stride) * (height + 1));
    const size_t out_bytes = static_cast<size_t>(out_stride) * (height + 1);
    Buffer expected(out_bytes), actual(out_bytes);
    reference.put_half_pel(window.at(offset), stride, width, height, fx, fy, expected.at(offset), out_stride);
    variant.put_half_pel(window.at(offset), stride, width, height, fx, fy, actual.at(offset), out_stride);
    if (auto diff =
            first_difference(expected.at(offset), actual.at(offset), out_bytes, static_cast<size_t>(out_stride));
        !diff.empty()) {
      return describe(diff, width, height, fx, fy, stride);
    }
  }
  return {};
}

std::string check_average(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    const int count = n < 3 ? std::array{256, 64, 16}[static_cast<size_t>(n)] : random.uniform(1, 600);
    const size_t offset = static_cast<size_t>(random.uniform(0, 15)), size = static_cast<size_t>(count);
    Buffer a(size + 16), b(size + 16), expected(size + 32), actual(size + 32);
    random.fill_with_extremes(a.at(offset), size);
    random.fill_with_extremes(b.at(1), size);
    reference.average(a.at(offset), b.at(1), count, expected.at(offset));
    const bool in_place = random.uniform(0, 3) == 0;  // out may alias an input
    if (in_place) {
      std::copy_n(a.at(offset), size, actual.at(offset));
      variant.average(actual.at(offset), b.at(1), count, actual.at(offset));
    } else {
      variant.average(a.at(offset), b.at(1), count, actual.at(offset));
    }
    if (auto diff = first_difference(expected.at(offset), actual.at(offset), size + 16); !diff.empty()) {
      return diff + " (count " + std::to_string(count) + (in_place ? ", in place)" : ")");
    }
  }
  return {};
}

std::string check_sad(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    const ptrdiff_t stride = 16 + random.uniform(0, 70);
    const size_t offset = static_cast<size_t>(random.uniform(0, 15));
    Buffer source(static_cast<size_t>(stride) * 16), prediction(256);
    random.fill_with_extremes(source.at(offset), static_cast<size_t>(stride) * 16);
    if (n % 7 == 0) {  // the largest SAD: every sample at the opposite extreme
      for (int i = 0; i < 256; ++i) source.at(offset)[i / 16 * stride + i % 16] = 255;
      std::fill_n(prediction.at(3), 256, uint8_t{0});
    } else {
      random.fill_with_extremes(prediction.at(3), 256);
    }
    const int expected = reference.sad_16x16(source.at(offset), stride, prediction.at(3));
    const int actual = variant.sad_16x16(source.at(offset), stride, prediction.at(3));
    if (expected != actual) {
      return "SAD: reference " + std::to_string(expected) + ", variant " + std::to_string(actual) + " (stride " +
             std::to_string(stride) + ")";
    }
  }
  return {};
}

// The contract: exact when the SAD is within the limit, otherwise any value above it.
std::string check_sad_half_pel(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    const int fx = n & 1, fy = (n >> 1) & 1;
    const ptrdiff_t reference_stride = 17 + random.uniform(0, 60), source_stride = 16 + random.uniform(0, 60);
    Buffer plane(static_cast<size_t>(reference_stride) * 17 + 16), source(static_cast<size_t>(source_stride) * 16);
    const size_t offset = static_cast<size_t>(random.uniform(0, 15));
    random.fill_with_extremes(plane.at(offset), static_cast<size_t>(reference_stride) * 17);
    random.fill_with_extremes(source.at(1), static_cast<size_t>(source_stride) * 16);
    const int exact = reference.sad_half_pel_16x16(plane.at(offset), reference_stride, fx, fy, source.at(1),
                                                   source_stride, 1 << 30);
    const std::array<int, 5> limits = {1 << 30, exact, std::max(exact - 1, 0), 0, random.uniform(0, exact + 1)};
    for (int limit : limits) {
      const int actual = variant.sad_half_pel_16x16(plane.at(offset), reference_stride, fx, fy, source.at(1),
                                                    source_stride, limit);
      if (exact <= limit ? actual != exact : actual <= limit) {
        return "SAD " + std::to_string(actual) + " with limit " + std::to_string(limit) + ", exact " +
               std::to_string(exact) + " (fx " + std::to_string(fx) + ", fy " + std::to_string(fy) + ")";
      }
    }
  }
  return {};
}

// A row of a warped block as warp_prediction.cc builds it, from random corner nodes
// (1/8 pel) at a random block position of a `size`-pixel plane, with every tap inside.
WarpRow random_warp_row(Random& random, int size, int count) {
  const int denominator = 2 * count, range = random.uniform(0, 1) ? 40 : 400;
  for (;;) {
    int nx[4], ny[4];
    for (int i = 0; i < 4; ++i) {
      nx[i] = random.uniform(-range, range);
      ny[i] = random.uniform(-range, range);
    }
    const int x0 = random.uniform(0, size - count), y0 = random.uniform(0, size - count),
              v = random.uniform(0, count - 1);
    const int b = 2 * v + 1;
    const int left_x = (denominator - b) * nx[0] + b * nx[2], right_x = (denominator - b) * nx[1] + b * nx[3];
    const int left_y = (denominator - b) * ny[0] + b * ny[2], right_y = (denominator - b) * ny[1] + b * ny[3];
    const int slope_x = right_x - left_x, slope_y = right_y - left_y;
    const WarpRow row{16 * x0,
                      16 * (y0 + v),
                      denominator * left_x + slope_x,
                      denominator * left_y + slope_y,
                      2 * slope_x,
                      2 * slope_y,
                      count == 16 ? 9 : 8,
                      count};
    bool inside = true;
    const int round = 1 << (row.shift - 1);
    for (int u = 0; u < count && inside; ++u) {
      const int X = row.x16 + 16 * u + ((row.sx + u * row.step_x + round) >> row.shift);
      const int Y = row.y16 + ((row.sy + u * row.step_y + round) >> row.shift);
      inside = X >= 0 && Y >= 0 && (X >> 4) + 1 < size && (Y >> 4) + 1 < size;
    }
    if (inside) return row;
  }
}

std::string check_warp_row(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  constexpr int kSize = 96;
  Buffer plane(kSize * kSize);
  for (int n = 0; n < iterations; ++n) {
    if (n % 16 == 0) random.fill_with_extremes(plane.at(0), kSize * kSize);
    const int count = n & 1 ? 8 : 16;
    const WarpRow row = random_warp_row(random, kSize, count);
    Buffer expected(count + 16), actual(count + 16);
    reference.warp_row(plane.at(0), kSize, row, expected.at(0));
    variant.warp_row(plane.at(0), kSize, row, actual.at(0));
    if (auto diff = first_difference(expected.at(0), actual.at(0), static_cast<size_t>(count) + 16);
        !diff.empty()) {
      return diff + " (count " + std::to_string(count) + ", x16 " + std::to_string(row.x16) + ", y16 " +
             std::to_string(row.y16) + ", sx " + std::to_string(row.sx) + ", step_x " + std::to_string(row.step_x) +
             ")";
    }
  }
  return {};
}

struct BenchPlane {
  std::vector<uint8_t> samples = std::vector<uint8_t>(64 * 64);
  BenchPlane() {
    for (size_t i = 0; i < samples.size(); ++i) samples[i] = static_cast<uint8_t>((i * 7 + i / 64 * 13) & 255);
  }
};

void bench_put_half_pel(const Tables& table, int iterations) {
  const BenchPlane plane;
  uint8_t out[256];
  for (int n = 0; n < iterations; ++n)
    table.put_half_pel(plane.samples.data() + (n & 7), 64, 16, 16, n & 1, (n >> 1) & 1, out, 16);
  bench_sink = out[5];
}

void bench_average(const Tables& table, int iterations) {
  const BenchPlane plane;
  uint8_t out[256];
  for (int n = 0; n < iterations; ++n)
    table.average(plane.samples.data() + (n & 7), plane.samples.data() + 512, 256, out);
  bench_sink = out[5];
}

void bench_sad(const Tables& table, int iterations) {
  const BenchPlane plane;
  int sum = 0;
  for (int n = 0; n < iterations; ++n)
    sum += table.sad_16x16(plane.samples.data() + (n & 7), 64, plane.samples.data() + 2048);
  bench_sink = sum;
}

void bench_sad_half_pel(const Tables& table, int iterations) {
  const BenchPlane plane;
  int sum = 0;
  for (int n = 0; n < iterations; ++n) {
    sum += table.sad_half_pel_16x16(plane.samples.data() + (n & 7), 64, n & 1, (n >> 1) & 1,
                                    plane.samples.data() + 2048, 64, 1 << 30);
  }
  bench_sink = sum;
}

void bench_warp_row(const Tables& table, int iterations) {
  const BenchPlane plane;
  uint8_t out[16];
  const WarpRow row{16 * 20, 16 * 20, 32 * 37 + 11, 32 * -23 + 5, 2 * 41, 2 * -17, 9, 16};
  for (int n = 0; n < iterations; ++n) table.warp_row(plane.samples.data() + (n & 7), 64, row, out);
  bench_sink = out[5];
}

}  // namespace

std::vector<Kernel> motion_kernels() {
  return {
      {"put_half_pel", [](const Tables& t) { return entry_of(t.put_half_pel); }, check_put_half_pel,
       bench_put_half_pel},
      {"average", [](const Tables& t) { return entry_of(t.average); }, check_average, bench_average},
      {"sad_16x16", [](const Tables& t) { return entry_of(t.sad_16x16); }, check_sad, bench_sad},
      {"sad_half_pel_16x16", [](const Tables& t) { return entry_of(t.sad_half_pel_16x16); }, check_sad_half_pel,
       bench_sad_half_pel},
      {"warp_row", [](const Tables& t) { return entry_of(t.warp_row); }, check_warp_row, bench_warp_row},
  };
}

}  // namespace svc::checkkernels
