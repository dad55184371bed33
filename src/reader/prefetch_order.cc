// SPDX-License-Identifier: BSD-2-Clause
#include "reader/prefetch_order.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace svc::reader_internal {

std::array<double, 3> GridGeometry::centre(const CellIndex& cell) const {
  const int32_t index[3] = {cell.x, cell.y, cell.z};
  std::array<double, 3> c{};
  for (int axis = 0; axis < 3; ++axis) c[axis] = origin[axis] + index[axis] * spacing[axis];
  return c;
}

CellIndex GridGeometry::cell_at(const std::array<double, 3>& p) const {
  int32_t index[3];
  for (int axis = 0; axis < 3; ++axis) {
    // Cell i covers centre +- spacing/2, as Reader::find_cell_at.
    const double t = std::floor((p[axis] - origin[axis]) / spacing[axis] + 0.5);
    index[axis] = static_cast<int32_t>(std::clamp(t, 0.0, static_cast<double>(std::max(dims[axis], 1) - 1)));
  }
  return CellIndex{index[0], index[1], index[2]};
}

std::vector<size_t> prefetch_order(const GridGeometry& grid, const CellIndex& viewer_cell,
                                   const std::array<double, 3>& viewer_position,
                                   const std::array<double, 3>& velocity, int radius, size_t max_cells,
                                   const std::function<std::optional<size_t>(const CellIndex&)>& find) {
  const double speed = std::sqrt(velocity[0] * velocity[0] + velocity[1] * velocity[1] + velocity[2] * velocity[2]);
  struct Candidate {
    int ring;
    double ahead;  // negated cosine: smaller is further ahead
    double distance;
    size_t ordinal;
  };
  std::vector<Candidate> candidates;
  const int32_t lo[3] = {std::max(viewer_cell.x - radius, 0), std::max(viewer_cell.y - radius, 0),
                         std::max(viewer_cell.z - radius, 0)};
  const int32_t hi[3] = {std::min(viewer_cell.x + radius, grid.dims[0] - 1),
                         std::min(viewer_cell.y + radius, grid.dims[1] - 1),
                         std::min(viewer_cell.z + radius, grid.dims[2] - 1)};
  for (int32_t y = lo[1]; y <= hi[1]; ++y) {
    for (int32_t z = lo[2]; z <= hi[2]; ++z) {
      for (int32_t x = lo[0]; x <= hi[0]; ++x) {
        const CellIndex cell{x, y, z};
        const std::optional<size_t> ordinal = find(cell);
        if (!ordinal) continue;
        const int ring =
            std::max({std::abs(x - viewer_cell.x), std::abs(y - viewer_cell.y), std::abs(z - viewer_cell.z)});
        const std::array<double, 3> c = grid.centre(cell);
        double d[3], length2 = 0, along = 0;
        for (int axis = 0; axis < 3; ++axis) {
          d[axis] = c[axis] - viewer_position[axis];
          length2 += d[axis] * d[axis];
          along += d[axis] * velocity[axis];
        }
        const double distance = std::sqrt(length2);
        const double cosine = (speed > 0 && distance > 0) ? along / (speed * distance) : 0.0;
        candidates.push_back(Candidate{ring, -cosine, distance, *ordinal});
      }
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.ring, a.ahead, a.distance, a.ordinal) < std::tie(b.ring, b.ahead, b.distance, b.ordinal);
  });
  std::vector<size_t> order;
  for (const Candidate& c : candidates) {
    if (order.size() >= max_cells) break;
    order.push_back(c.ordinal);
  }
  return order;
}

}  // namespace svc::reader_internal
