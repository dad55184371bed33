// SPDX-License-Identifier: BSD-2-Clause
// The scans and position contexts of every transform size, tabulated at compile time.
#include "codec/common/coefficient_contexts.h"

#include <algorithm>
#include <bit>

namespace svc::codec {

constexpr std::array<uint8_t, 64> kZigZag = {
    0,  1,  8,  16, 9,  2,  3,  10, 17, 24, 32, 25, 18, 11, 4,  5,   //
    12, 19, 26, 33, 40, 48, 41, 34, 27, 20, 13, 6,  7,  14, 21, 28,  //
    35, 42, 49, 56, 57, 50, 43, 36, 29, 22, 15, 23, 30, 37, 44, 51,  //
    58, 59, 52, 45, 38, 31, 39, 46, 53, 60, 61, 54, 47, 55, 62, 63,  //
};

namespace {

// The zig-zag of an N x N block: anti-diagonals in increasing order, odd ones from the
// top right down, even ones from the bottom left up (MPEG-2's order for N = 8).
template <int W, int H = W>
constexpr std::array<uint8_t, W * H> zig_zag() {
  std::array<uint8_t, W * H> scan{};
  int i = 0;
  for (int d = 0; d <= W + H - 2; ++d) {
    for (int k = 0; k <= d; ++k) {
      const int row = d % 2 ? k : d - k, column = d - row;
      if (row < H && column < W) scan[static_cast<size_t>(i++)] = static_cast<uint8_t>(W * row + column);
    }
  }
  return scan;
}

constexpr int diagonal_class(int row, int column) {
  const int diagonal = row + column;
  return diagonal == 0 ? 0 : diagonal <= 2 ? 1 : diagonal <= 5 ? 2 : 3;
}

template <int W, int H = W>
constexpr std::array<PositionContext, W * H> position_contexts() {
  std::array<PositionContext, W * H> table{};
  for (int row = 0; row < H; ++row) {
    for (int column = 0; column < W; ++column) {
      PositionContext& entry = table[static_cast<size_t>(row * W + column)];
      entry.grid = static_cast<uint16_t>(row * (W + 2) + column);
      entry.position_class = static_cast<uint8_t>(diagonal_class(row, column));
      entry.range_group = static_cast<uint8_t>(row + column == 0 ? 0 : (row < 2 && column < 2 ? 1 : 2));
      entry.position = static_cast<uint8_t>(row * W + column);
    }
  }
  return table;
}

template <size_t N>
constexpr std::array<PositionContext, N> in_scan_order(const std::array<uint8_t, N>& scan,
                                                       const std::array<PositionContext, N>& positions) {
  std::array<PositionContext, N> table{};
  for (size_t i = 0; i < N; ++i) table[i] = positions[scan[i]];
  return table;
}

// One size's scan and its positions' context inputs by scan index.
template <int W, int H = W>
struct SizeTables {
  static constexpr std::array<uint8_t, W* H> scan = zig_zag<W, H>();
  static constexpr std::array<PositionContext, W* H> scanned = in_scan_order(scan, position_contexts<W, H>());
  static constexpr ScanOrder order{W, H, W* H, scan.data(), scanned.data()};
};
static_assert(SizeTables<8>::scan == kZigZag, "the 8x8 scan is MPEG-2's zig-zag");

}  // namespace

const ScanOrder& scan_order(TransformSize size) {
  switch (size) {
    case TransformSize::k4x4: return SizeTables<4>::order;
    case TransformSize::k16x16: return SizeTables<16>::order;
    case TransformSize::k16x8: return SizeTables<16, 8>::order;
    case TransformSize::k8x16: return SizeTables<8, 16>::order;
    case TransformSize::k16x4: return SizeTables<16, 4>::order;
    case TransformSize::k4x16: return SizeTables<4, 16>::order;
    case TransformSize::k8x4: return SizeTables<8, 4>::order;
    case TransformSize::k4x8: return SizeTables<4, 8>::order;
    default: return SizeTables<8>::order;
  }
}

int NeighbourMagnitudes::range_context(const PositionContext& p) const {
  const uint16_t* a = grid_.data() + p.grid;
  const int s = stride_;
  const int magnitude = std::min<int>(a[1], 15) + std::min<int>(a[s], 15) + std::min<int>(a[s + 1], 15);
  return p.range_group * 7 + std::min((magnitude + 1) >> 1, 6);
}

int NeighbourMagnitudes::rice_parameter(const PositionContext& p) const {
  const uint16_t* a = grid_.data() + p.grid;
  const int s = stride_;
  const unsigned sum = unsigned{a[1]} + a[s] + a[s + 1] + a[2] + a[2 * s];
  return std::min(kMaxRiceParameter, static_cast<int>(std::bit_width(sum >> 6)));
}

}  // namespace svc::codec
