// SPDX-License-Identifier: BSD-2-Clause
// Color-conversion row kernels against their references: every width up to 40 and
// random wider rows, unaligned rows, extremes that saturate the clamps. The YCbCr rows
// (RGB, RGBA, BGRA) share one check and one benchmark.
#include <algorithm>

#include "checkkernels/harness.h"

namespace svc::checkkernels {
namespace {

int random_width(Random& random, int n) { return n < 40 ? n + 1 : random.uniform(1, 1100); }

std::string with_input(const std::string& diff, int width, size_t offset) {
  return diff + " (width " + std::to_string(width) + ", offset " + std::to_string(offset) + ")";
}

std::string check_luma_row(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations + 40; ++n) {
    const int width = random_width(random, n);
    const size_t offset = static_cast<size_t>(random.uniform(0, 15));
    Buffer rgb(3 * static_cast<size_t>(width) + 16), expected(static_cast<size_t>(width) + 32),
        actual(static_cast<size_t>(width) + 32);
    random.fill_with_extremes(rgb.at(offset), 3 * static_cast<size_t>(width));
    reference.rgb_to_luma_row(rgb.at(offset), width, expected.at(offset));
    variant.rgb_to_luma_row(rgb.at(offset), width, actual.at(offset));
    // One row plus the bytes after it: a variant must not write past the row.
    if (auto diff = first_difference(expected.at(0), actual.at(0), width + 32); !diff.empty()) {
      return with_input(diff, width, offset);
    }
  }
  return {};
}

std::string check_chroma_row(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  for (int n = 0; n < iterations + 40; ++n) {
    const int width = random_width(random, n), chroma_width = (width + 1) / 2;
    const size_t offset = static_cast<size_t>(random.uniform(0, 15)), row_bytes = 3 * static_cast<size_t>(width);
    Buffer rgb(2 * row_bytes + 16);
    random.fill_with_extremes(rgb.at(offset), 2 * row_bytes);
    const uint8_t* row0 = rgb.at(offset);
    const uint8_t* row1 = random.uniform(0, 3) == 0 ? row0 : row0 + row_bytes;  // last row of an odd height
    Buffer expected(2 * static_cast<size_t>(chroma_width) + 64), actual(2 * static_cast<size_t>(chroma_width) + 64);
    const size_t cr_offset = static_cast<size_t>(chroma_width) + 32;
    reference.rgb_to_chroma_row(row0, row1, width, expected.at(0), expected.at(cr_offset));
    variant.rgb_to_chroma_row(row0, row1, width, actual.at(0), actual.at(cr_offset));
    if (auto diff = first_difference(expected.at(0), actual.at(0), cr_offset + chroma_width + 32); !diff.empty()) {
      return with_input(diff + " (cb then cr from index " + std::to_string(cr_offset) + ")", width, offset);
    }
  }
  return {};
}

using codec::dsp::DspTable;

// One of the shared table's YCbCr row entries, which differ only in their output layout.
using YcbcrRow = decltype(&DspTable::ycbcr_to_rgb_row);

// `row` writes kBytes per pixel. Planes and output at their own unaligned offsets; the
// comparison spans the bytes before and after the output too, so a variant that writes
// outside its row fails.
template <YcbcrRow row, size_t kBytes>
std::string check_ycbcr_row(const Tables& reference, const Tables& variant, Random& random, int iterations) {
  constexpr size_t kGuard = 64;  // a whole group of 16 four-byte pixels
  for (int n = 0; n < iterations + 40; ++n) {
    const int width = random_width(random, n), chroma_width = (width + 1) / 2;
    const size_t offset = static_cast<size_t>(random.uniform(0, 15));
    const size_t out_offset = static_cast<size_t>(random.uniform(0, 15));
    Buffer planes(static_cast<size_t>(width) + 2 * static_cast<size_t>(chroma_width) + 16);
    uint8_t* y = planes.at(offset);
    uint8_t* cb = y + width;
    uint8_t* cr = cb + chroma_width;
    random.fill_with_extremes(y, static_cast<size_t>(width));
    random.fill_with_extremes(cb, static_cast<size_t>(chroma_width));
    random.fill_with_extremes(cr, static_cast<size_t>(chroma_width));
    const size_t row_bytes = kBytes * static_cast<size_t>(width);
    Buffer expected(row_bytes + kGuard + 16), actual(row_bytes + kGuard + 16);
    (reference.*row)(y, cb, cr, width, expected.at(out_offset));
    (variant.*row)(y, cb, cr, width, actual.at(out_offset));
    if (auto diff = first_difference(expected.at(0), actual.at(0), out_offset + row_bytes + kGuard);
        !diff.empty()) {
      return with_input(diff + " (output offset " + std::to_string(out_offset) + ")", width, offset);
    }
  }
  return {};
}

constexpr int kBenchWidth = 512;  // a face row

void bench_luma_row(const Tables& table, int iterations) {
  std::vector<uint8_t> rgb(3 * kBenchWidth), y(kBenchWidth);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<uint8_t>(i * 31);
  for (int n = 0; n < iterations; ++n) table.rgb_to_luma_row(rgb.data(), kBenchWidth, y.data());
  bench_sink = y[7];
}

void bench_chroma_row(const Tables& table, int iterations) {
  std::vector<uint8_t> rgb(6 * kBenchWidth), cb(kBenchWidth / 2), cr(kBenchWidth / 2);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<uint8_t>(i * 31);
  for (int n = 0; n < iterations; ++n) {
    table.rgb_to_chroma_row(rgb.data(), rgb.data() + 3 * kBenchWidth, kBenchWidth, cb.data(), cr.data());
  }
  bench_sink = cb[7] + cr[7];
}

template <YcbcrRow row, size_t kBytes>
void bench_ycbcr_row(const Tables& table, int iterations) {
  std::vector<uint8_t> planes(2 * kBenchWidth), out(kBytes * kBenchWidth);
  for (size_t i = 0; i < planes.size(); ++i) planes[i] = static_cast<uint8_t>(i * 31);
  const uint8_t* y = planes.data();
  for (int n = 0; n < iterations; ++n) {
    (table.*row)(y, y + kBenchWidth, y + kBenchWidth + kBenchWidth / 2, kBenchWidth, out.data());
  }
  bench_sink = out[7];
}

}  // namespace

std::vector<Kernel> color_kernels() {
  return {
      {"rgb_to_luma_row", [](const Tables& t) { return entry_of(t.rgb_to_luma_row); }, check_luma_row,
       bench_luma_row},
      {"rgb_to_chroma_row", [](const Tables& t) { return entry_of(t.rgb_to_chroma_row); }, check_chroma_row,
       bench_chroma_row},
      {"ycbcr_to_rgb_row", [](const Tables& t) { return entry_of(t.ycbcr_to_rgb_row); },
       check_ycbcr_row<&DspTable::ycbcr_to_rgb_row, 3>, bench_ycbcr_row<&DspTable::ycbcr_to_rgb_row, 3>},
      {"ycbcr_to_rgba_row", [](const Tables& t) { return entry_of(t.ycbcr_to_rgba_row); },
       check_ycbcr_row<&DspTable::ycbcr_to_rgba_row, 4>, bench_ycbcr_row<&DspTable::ycbcr_to_rgba_row, 4>},
      {"ycbcr_to_bgra_row", [](const Tables& t) { return entry_of(t.ycbcr_to_bgra_row); },
       check_ycbcr_row<&DspTable::ycbcr_to_bgra_row, 4>, bench_ycbcr_row<&DspTable::ycbcr_to_bgra_row, 4>},
  };
}

}  // namespace svc::checkkernels
