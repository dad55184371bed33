// SPDX-License-Identifier: BSD-2-Clause
// Which cells to prefetch around a viewer, most urgent first. Pure computation.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "svc/types.h"

namespace svc::reader_internal {

struct GridGeometry {
  std::array<int32_t, 3> dims{1, 1, 1};
  std::array<double, 3> origin{0, 0, 0};
  std::array<double, 3> spacing{1, 1, 1};

  std::array<double, 3> centre(const CellIndex& cell) const;
  // The grid cell containing `p`, clamped into the grid. Precondition: p finite.
  CellIndex cell_at(const std::array<double, 3>& p) const;
};

// The present cells (ordinals returned by `find`) within `radius` cells of `viewer_cell`
// along every axis, ordered by: ring (Chebyshev distance from viewer_cell, nearest
// first), then how far ahead they lie along `velocity` (cosine of the angle between the
// velocity and the direction from `viewer_position` to the cell centre; ahead first;
// ignored when the velocity is zero), then Euclidean distance from viewer_position, then
// ordinal. At most `max_cells` are returned. Deterministic.
std::vector<size_t> prefetch_order(const GridGeometry& grid, const CellIndex& viewer_cell,
                                   const std::array<double, 3>& viewer_position,
                                   const std::array<double, 3>& velocity, int radius, size_t max_cells,
                                   const std::function<std::optional<size_t>(const CellIndex&)>& find);

}  // namespace svc::reader_internal
