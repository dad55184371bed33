// SPDX-License-Identifier: BSD-2-Clause
// Motion-compensation kernels against their references: the 8-tap interpolation at every
// luma and chroma phase pair, every block width the codec uses (4 for warped
// sub-blocks, 8, 16) and others up to 64, odd strides, unaligned pointers, extreme
// samples (the largest positive and negative sums of both passes) and the samples
// around each output block; the rounding and averaging of intermediates over their whole
// range; the SAD.
#include <algorithm>
#include <array>

#include "checkkernels/harness.h"
#include "codec/common/motion_compensation.h"

namespace svc::checkkernels {
namespace {

constexpr std::array<int, 8> kBlockWidths = {16, 8, 4, 12, 20, 32, 48, 64};

// Taps of a random phase (luma 0..3 or chroma 0..7) of a random bank.
const int8_t* random_taps(Random& random, int n) {
  const bool luma = (n & 1) == 0;
  const auto filter =
      static_cast<codec::InterpolationFilter>(random.uniform(0, codec::kInterpolationFilterCount - 1));
  return codec::interpolation_taps(luma ? codec::PlaneKind::kLuma : codec::PlaneKind::kChroma,
                                   random.uniform(0, luma ? 3 : 7), filter)
      .data();
}

std::string compare_interpolation(const Tables& reference, const Tables& variant, Random& random, int width,
                                  int height, const int8_t* h, const int8_t* v) {
  // Rows hold width + 7 samples and may be read 8 past them (dsp.h).
  const ptrdiff_t stride = width + 15 + random.uniform(0, 21), out_stride = width + random.uniform(0, 9);
  const size_t offset = static_cast<size_t>(random.uniform(0, 15));
  Buffer window(static_cast<size_t>(stride) * (height + 7) + 16);
  random.fill_with_extremes(window.at(offset), static_cast<size_t>(stride) * (height + 7));
  const size_t out_count = static_cast<size_t>(out_stride) * (height + 1);
  Buffer expected(out_count * 2), actual(out_count * 2);
  auto* expected_out = reinterpret_cast<int16_t*>(expected.at(2 * offset));
  auto* actual_out = reinterpret_cast<int16_t*>(actual.at(2 * offset));
  reference.interpolate_8tap(window.at(offset), stride, width, height, h, v, expected_out, out_stride);
  variant.interpolate_8tap(window.at(offset), stride, width, height, h, v, actual_out, out_stride);
  if (auto diff = first_difference(expected_out, actual_out, out_count, static_cast<size_t>(out_stride));
      !diff.empty()) {
    return diff + " (block " + std::to_string(width) + "x" + std::to_string(height) + ", h taps " +
           std::to_string(h[2]) + "/" + std::to_string(h[3]) + "/" + std::to_string(h[4]) + ", v taps " +
           std::to_string(v[2]) + "/" + std::to_string(v[3]) + "/" + std::to_string(v[4]) + ", stride " +
           std::to_string(stride) + ")";
  }
  return {};
}

// Every phase pair of every bank and plane kind once, then random blocks and phases.
std::string check_interpolate(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  int n = 0;
  for (int f = 0; f < codec::kInterpolationFilterCount; ++f) {
    const auto filter = static_cast<codec::InterpolationFilter>(f);
    for (const auto kind : {codec::PlaneKind::kLuma, codec::PlaneKind::kChroma}) {
      const int phases = kind == codec::PlaneKind::kLuma ? 4 : 8;
      for (int pair = 0; pair < phases * phases; ++pair, ++n) {
        const int width = kBlockWidths[static_cast<size_t>(n) % kBlockWidths.size()];
        const int8_t* h = codec::interpolation_taps(kind, pair % phases, filter).data();
        const int8_t* v = codec::interpolation_taps(kind, pair / phases, filter).data();
        if (auto diff = compare_interpolation(reference, variant, random, width, random.uniform(1, 16), h, v);
            !diff.empty()) {
          return diff;
        }
      }
    }
  }
  for (n = 0; n < iterations; ++n) {
    const int width = kBlockWidths[static_cast<size_t>(n) % kBlockWidths.size()];
    const int height = n % 3 == 0 ? width : random.uniform(1, 64);
    const int8_t* h = random_taps(random, n);
    const int8_t* v = random_taps(random, n >> 1);
    if (auto diff = compare_interpolation(reference, variant, random, width, height, h, v); !diff.empty())
      return diff;
  }
  return {};
}

// 4x4 blocks, the warped mode's, which variants may take a path of their own for: every
// phase pair of every bank and plane kind, then random phases.
std::string check_interpolate_4x4(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int f = 0; f < codec::kInterpolationFilterCount; ++f) {
    const auto filter = static_cast<codec::InterpolationFilter>(f);
    for (const auto kind : {codec::PlaneKind::kLuma, codec::PlaneKind::kChroma}) {
      const int phases = kind == codec::PlaneKind::kLuma ? 4 : 8;
      for (int pair = 0; pair < phases * phases; ++pair) {
        const int8_t* h = codec::interpolation_taps(kind, pair % phases, filter).data();
        const int8_t* v = codec::interpolation_taps(kind, pair / phases, filter).data();
        if (auto diff = compare_interpolation(reference, variant, random, 4, 4, h, v); !diff.empty()) return diff;
      }
    }
  }
  for (int n = 0; n < iterations; ++n) {
    const int8_t* h = random_taps(random, n);
    const int8_t* v = random_taps(random, n >> 1);
    if (auto diff = compare_interpolation(reference, variant, random, 4, 4, h, v); !diff.empty()) return diff;
  }
  return {};
}

// Intermediates over their whole range, sometimes at its ends.
void fill_intermediates(Random& random, int16_t* data, int count) {
  const int mode = random.uniform(0, 3);
  for (int i = 0; i < count; ++i) {
    if (mode == 0) {
      data[i] = static_cast<int16_t>((i & 1) ? 24958 : -25022);
    } else {
      data[i] = static_cast<int16_t>(random.uniform(-25022, 24958));
    }
  }
}

std::string check_rounding(const Tables& reference, const Tables& variant, Random& random, int iterations,
                           bool average) {
  for (int n = 0; n < iterations; ++n) {
    const int count = n < 3 ? std::array{256, 64, 16}[static_cast<size_t>(n)] : random.uniform(1, 600);
    const size_t size = static_cast<size_t>(count);
    std::vector<int16_t> a(size), b(size);
    fill_intermediates(random, a.data(), count);
    fill_intermediates(random, b.data(), count);
    const size_t offset = static_cast<size_t>(random.uniform(0, 15));
    Buffer expected(size + 32), actual(size + 32);
    if (average) {
      reference.average_intermediate(a.data(), b.data(), count, expected.at(offset));
      variant.average_intermediate(a.data(), b.data(), count, actual.at(offset));
    } else {
      reference.put_intermediate(a.data(), count, expected.at(offset));
      variant.put_intermediate(a.data(), count, actual.at(offset));
    }
    if (auto diff = first_difference(expected.at(offset), actual.at(offset), size + 16); !diff.empty()) {
      return diff + " (count " + std::to_string(count) + ")";
    }
  }
  return {};
}

std::string check_put(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  return check_rounding(reference, variant, random, iterations, false);
}

std::string check_average(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  return check_rounding(reference, variant, random, iterations, true);
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

std::string check_sad_average(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations; ++n) {
    const int width = random.uniform(0, 1) ? 16 : 8, height = random.uniform(1, 16);
    const ptrdiff_t source_stride = width + random.uniform(0, 70), reference_stride = width + random.uniform(0, 70);
    Buffer source(static_cast<size_t>(source_stride) * 16), planes(static_cast<size_t>(reference_stride) * 32);
    random.fill_with_extremes(source.at(0), static_cast<size_t>(source_stride) * 16);
    random.fill_with_extremes(planes.at(0), static_cast<size_t>(reference_stride) * 32);
    const uint8_t* a = planes.at(static_cast<size_t>(random.uniform(0, 15)));
    // b: the same block (a whole-sample or half-sample position) or one further on.
    const uint8_t* b = n % 3 == 0 ? a
                                  : planes.at(static_cast<size_t>(reference_stride) * 16 + random.uniform(0, 15));
    const int expected = reference.sad_average(source.at(0), source_stride, a, b, reference_stride, width, height);
    const int actual = variant.sad_average(source.at(0), source_stride, a, b, reference_stride, width, height);
    if (expected != actual) {
      return "SAD of average: reference " + std::to_string(expected) + ", variant " + std::to_string(actual) +
             " (" + std::to_string(width) + "x" + std::to_string(height) + ")";
    }
  }
  return {};
}

struct BenchPlane {
  std::vector<uint8_t> samples = std::vector<uint8_t>(96 * 96);
  BenchPlane() {
    for (size_t i = 0; i < samples.size(); ++i) samples[i] = static_cast<uint8_t>((i * 7 + i / 96 * 13) & 255);
  }
};

// size x size blocks, the 16 luma phase pairs in turn.
template <int size>
void bench_interpolate(const Tables& table, int iterations) {
  const BenchPlane plane;
  int16_t out[size * size];
  for (int n = 0; n < iterations; ++n) {
    const int8_t* h = codec::interpolation_taps(codec::PlaneKind::kLuma, n & 3).data();
    const int8_t* v = codec::interpolation_taps(codec::PlaneKind::kLuma, (n >> 2) & 3).data();
    table.interpolate_8tap(plane.samples.data() + (n & 7), 96, size, size, h, v, out, size);
  }
  bench_sink = out[5];
}

void bench_put(const Tables& table, int iterations) {
  int16_t in[256];
  for (int i = 0; i < 256; ++i) in[i] = static_cast<int16_t>(i * 97 - 8192);
  uint8_t out[256];
  for (int n = 0; n < iterations; ++n) table.put_intermediate(in, 256, out);
  bench_sink = out[5];
}

void bench_average(const Tables& table, int iterations) {
  int16_t a[256], b[256];
  for (int i = 0; i < 256; ++i) {
    a[i] = static_cast<int16_t>(i * 97 - 8192);
    b[i] = static_cast<int16_t>(i * 31 - 4000);
  }
  uint8_t out[256];
  for (int n = 0; n < iterations; ++n) table.average_intermediate(a, b, 256, out);
  bench_sink = out[5];
}

void bench_sad(const Tables& table, int iterations) {
  const BenchPlane plane;
  int sum = 0;
  for (int n = 0; n < iterations; ++n)
    sum += table.sad_16x16(plane.samples.data() + (n & 7), 96, plane.samples.data() + 2048);
  bench_sink = sum;
}

void bench_sad_average(const Tables& table, int iterations) {
  const BenchPlane plane;
  int sum = 0;
  for (int n = 0; n < iterations; ++n) {
    const uint8_t* a = plane.samples.data() + (n & 7);
    sum += table.sad_average(plane.samples.data() + 4096, 96, a, a + 97, 96, 16, 16);
  }
  bench_sink = sum;
}

}  // namespace

std::vector<Kernel> motion_kernels() {
  return {
      {"interpolate_8tap", [](const Tables& t) { return entry_of(t.interpolate_8tap); }, check_interpolate,
       bench_interpolate<16>},
      {"interpolate_8tap_4x4", [](const Tables& t) { return entry_of(t.interpolate_8tap); }, check_interpolate_4x4,
       bench_interpolate<4>},
      {"put_intermediate", [](const Tables& t) { return entry_of(t.put_intermediate); }, check_put, bench_put},
      {"average_intermediate", [](const Tables& t) { return entry_of(t.average_intermediate); }, check_average,
       bench_average},
      {"sad_16x16", [](const Tables& t) { return entry_of(t.sad_16x16); }, check_sad, bench_sad},
      {"sad_average", [](const Tables& t) { return entry_of(t.sad_average); }, check_sad_average,
       bench_sad_average},
  };
}

}  // namespace svc::checkkernels
