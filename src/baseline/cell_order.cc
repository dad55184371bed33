// SPDX-License-Identifier: BSD-2-Clause
// Cell orders of the baseline: row-major (dissertation Figure 4.1) and Hilbert (Figure 8.1).
#include <algorithm>
#include <tuple>
#include <utility>

#include "baseline/baseline.h"

namespace svc::baseline {

const char* cell_order_name(CellOrder order) {
  switch (order) {
    case CellOrder::kRowMajor: return "row-major";
    case CellOrder::kHilbert: return "hilbert";
  }
  return "unknown";
}

bool parse_cell_order(const std::string& name, CellOrder* out) {
  if (name == "row-major") {
    *out = CellOrder::kRowMajor;
    return true;
  }
  if (name == "hilbert") {
    *out = CellOrder::kHilbert;
    return true;
  }
  return false;
}

int CellSequence::frame_of(CellIndex cell) const {
  for (size_t k = 0; k < cells.size(); ++k) {
    if (cells[k] == cell) return static_cast<int>(k);
  }
  return -1;
}

uint64_t hilbert_distance(uint32_t n, uint32_t x, uint32_t z) {
  // The classic xy2d: at each scale pick the quadrant, then rotate/flip the remainder
  // into that quadrant's orientation.
  uint64_t distance = 0;
  for (uint64_t s = n / 2; s > 0; s /= 2) {
    const uint32_t rx = (x & s) ? 1 : 0;
    const uint32_t rz = (z & s) ? 1 : 0;
    distance += s * s * ((3 * rx) ^ rz);
    if (rz == 0) {
      if (rx == 1) {
        x = n - 1 - x;
        z = n - 1 - z;
      }
      std::swap(x, z);
    }
  }
  return distance;
}

Result<CellSequence> order_cells(std::span<const CellIndex> cells, std::array<int, 3> dims, CellOrder order,
                                 int hilbert_gop_length) {
  for (int axis = 0; axis < 3; ++axis) {
    if (dims[axis] < 1) {
      return Status(ErrorCode::kInvalidArgument,
                    "grid dims must be >= 1, axis " + std::to_string(axis) + " is " + std::to_string(dims[axis]));
    }
  }
  if (order == CellOrder::kHilbert && hilbert_gop_length < 1) {
    return Status(ErrorCode::kInvalidArgument,
                  "hilbert_gop_length must be >= 1, got " + std::to_string(hilbert_gop_length));
  }
  for (const CellIndex& c : cells) {
    if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= dims[0] || c.y >= dims[1] || c.z >= dims[2]) {
      return Status(ErrorCode::kInvalidArgument, cell_label(c) + " lies outside the grid");
    }
  }

  uint32_t side = 1;  // Hilbert grid: next power of two covering x and z
  while (side < static_cast<uint32_t>(std::max(dims[0], dims[2]))) side *= 2;

  struct Keyed {
    int64_t layer;
    uint64_t primary;   // row z (row-major) or Hilbert distance
    int64_t secondary;  // x (row-major), unused for Hilbert
    CellIndex cell;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(cells.size());
  for (const CellIndex& c : cells) {
    if (order == CellOrder::kRowMajor) {
      keyed.push_back({c.y, static_cast<uint64_t>(c.z), c.x, c});
    } else {
      keyed.push_back({c.y, hilbert_distance(side, static_cast<uint32_t>(c.x), static_cast<uint32_t>(c.z)), 0, c});
    }
  }
  std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    return std::tie(a.layer, a.primary, a.secondary) < std::tie(b.layer, b.primary, b.secondary);
  });

  CellSequence sequence;
  sequence.dims = dims;
  sequence.order = order;
  sequence.cells.reserve(keyed.size());
  sequence.gop_start.reserve(keyed.size());
  int64_t position_in_layer = 0;
  for (size_t k = 0; k < keyed.size(); ++k) {
    const bool new_layer = k == 0 || keyed[k].layer != keyed[k - 1].layer;
    if (k > 0 && keyed[k].cell == keyed[k - 1].cell) {
      return Status(ErrorCode::kInvalidArgument, cell_label(keyed[k].cell) + " is listed twice");
    }
    position_in_layer = new_layer ? 0 : position_in_layer + 1;
    bool starts_gop = false;
    if (order == CellOrder::kRowMajor) {
      starts_gop = new_layer || keyed[k].primary != keyed[k - 1].primary;
    } else {
      starts_gop = position_in_layer % hilbert_gop_length == 0;
    }
    sequence.cells.push_back(keyed[k].cell);
    sequence.gop_start.push_back(starts_gop ? 1 : 0);
  }
  return sequence;
}

}  // namespace svc::baseline
