#include "spatial/placement.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <string>

namespace svc {
namespace {

using GroupKey = std::array<int32_t, 3>;

std::string index_text(const CellIndex& c) {
  std::string text = "(";
  text += std::to_string(c.x);
  text += ", ";
  text += std::to_string(c.y);
  text += ", ";
  text += std::to_string(c.z);
  text += ")";
  return text;
}

// A candidate cell ranked by distance, then by (y, z, x) index.
struct Ranked {
  double distance_squared = 0;
  CellIndex index;
  uint32_t ordinal = 0;
};

// True when `a` ranks before `b`. Distances equal within a relative 1e-9 are ties, so
// that symmetric configurations do not depend on rounding of the grid spacing.
bool ranks_before(const Ranked& a, const Ranked& b) {
  const double scale = std::max(a.distance_squared, b.distance_squared);
  if (std::abs(a.distance_squared - b.distance_squared) > 1e-9 * scale) {
    return a.distance_squared < b.distance_squared;
  }
  if (a.index.y != b.index.y) return a.index.y < b.index.y;
  if (a.index.z != b.index.z) return a.index.z < b.index.z;
  return a.index.x < b.index.x;
}

double distance_squared(const std::array<double, 3>& a, const CellIndex& b, const std::array<double, 3>& spacing) {
  const double dx = (a[0] - b.x) * spacing[0];
  const double dy = (a[1] - b.y) * spacing[1];
  const double dz = (a[2] - b.z) * spacing[2];
  return dx * dx + dy * dy + dz * dz;
}

std::array<double, 3> as_point(const CellIndex& c) {
  return {static_cast<double>(c.x), static_cast<double>(c.y), static_cast<double>(c.z)};
}

Status validate(const std::vector<CellIndex>& cells, const std::array<int32_t, 3>& dims,
                const PlacementSettings& settings, const std::array<double, 3>& grid_spacing) {
  static constexpr const char* kAxis[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (dims[a] <= 0) {
      return Status(ErrorCode::kInvalidArgument, std::string("placement: grid dims along ") + kAxis[a] + " is " +
                                                     std::to_string(dims[a]) + ", must be > 0");
    }
    const int32_t s = settings.i_spacing[a];
    if (s < 1 || s > kMaxIntraSpacing) {
      return Status(ErrorCode::kInvalidArgument, std::string("placement: i_spacing along ") + kAxis[a] + " is " +
                                                     std::to_string(s) + ", must be in 1.." +
                                                     std::to_string(kMaxIntraSpacing));
    }
    if (!std::isfinite(grid_spacing[a]) || grid_spacing[a] <= 0) {
      return Status(ErrorCode::kInvalidArgument, std::string("placement: grid spacing along ") + kAxis[a] + " is " +
                                                     std::to_string(grid_spacing[a]) + ", must be finite and > 0");
    }
  }
  if (cells.size() > UINT32_MAX) {
    return Status(ErrorCode::kInvalidArgument, "placement: too many cells");
  }
  return Status::Ok();
}

}  // namespace

Result<std::vector<CellPlacement>> place_cubes(const std::vector<CellIndex>& cells,
                                               const std::array<int32_t, 3>& dims,
                                               const PlacementSettings& settings,
                                               const std::array<double, 3>& grid_spacing) {
  SVC_RETURN_IF_ERROR(validate(cells, dims, settings, grid_spacing));
  const auto& s = settings.i_spacing;

  // Group membership, keyed by group index; std::map keeps every later step independent
  // of the order of `cells`.
  std::map<GroupKey, std::vector<uint32_t>> groups;
  std::map<std::array<int32_t, 3>, uint32_t> seen;
  for (uint32_t ordinal = 0; ordinal < cells.size(); ++ordinal) {
    const CellIndex& c = cells[ordinal];
    if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= dims[0] || c.y >= dims[1] || c.z >= dims[2]) {
      return Status(ErrorCode::kInvalidArgument,
                    "placement: cell " + index_text(c) + " lies outside the grid dims (" + std::to_string(dims[0]) +
                        ", " + std::to_string(dims[1]) + ", " + std::to_string(dims[2]) + ")");
    }
    if (!seen.emplace(std::array<int32_t, 3>{c.x, c.y, c.z}, ordinal).second) {
      return Status(ErrorCode::kInvalidArgument, "placement: cell " + index_text(c) + " is listed twice");
    }
    groups[{c.x / s[0], c.y / s[1], c.z / s[2]}].push_back(ordinal);
  }

  // One I-cube per non-empty group: the nominal cell, or the present cell nearest to it.
  std::map<GroupKey, uint32_t> group_intra;
  std::vector<CellPlacement> placement(cells.size());
  for (const auto& [key, members] : groups) {
    const std::array<double, 3> nominal = {static_cast<double>(key[0] * s[0] + s[0] / 2),
                                           static_cast<double>(key[1] * s[1] + s[1] / 2),
                                           static_cast<double>(key[2] * s[2] + s[2] / 2)};
    Ranked best;
    bool have_best = false;
    for (uint32_t ordinal : members) {
      const Ranked candidate{distance_squared(nominal, cells[ordinal], grid_spacing), cells[ordinal], ordinal};
      if (!have_best || ranks_before(candidate, best)) {
        best = candidate;
        have_best = true;
      }
    }
    group_intra[key] = best.ordinal;
  }
  for (uint32_t ordinal = 0; ordinal < cells.size(); ++ordinal) placement[ordinal].intra = false;
  for (const auto& [key, ordinal] : group_intra) placement[ordinal].intra = true;

  // References: the two nearest I-cubes among the own and adjacent groups.
  ReachIndex reach(s);
  for (const auto& [key, ordinal] : group_intra) reach.add({cells[ordinal], ordinal});
  for (uint32_t ordinal = 0; ordinal < cells.size(); ++ordinal) {
    if (placement[ordinal].intra) continue;
    const CellIndex& c = cells[ordinal];
    auto& refs = placement[ordinal].references;
    refs = reach.references(c, grid_spacing);
    if (refs.empty()) {
      return Status(ErrorCode::kInternal, "placement: B-cube " + index_text(c) + " has no I-cube in its own group");
    }
  }
  return placement;
}

Result<std::vector<CellPlacement>> place_cubes(const std::vector<CellIndex>& cells,
                                               const std::array<int32_t, 3>& dims,
                                               const PlacementSettings& settings) {
  return place_cubes(cells, dims, settings, {1.0, 1.0, 1.0});
}

void ReachIndex::add(const ReferenceCandidate& candidate) {
  const CellIndex& c = candidate.index;
  by_group_[{c.x / spacing_[0], c.y / spacing_[1], c.z / spacing_[2]}].push_back(candidate);
}

std::vector<uint32_t> ReachIndex::references(const CellIndex& cell,
                                             const std::array<double, 3>& grid_spacing) const {
  const GroupKey own = {cell.x / spacing_[0], cell.y / spacing_[1], cell.z / spacing_[2]};
  std::vector<ReferenceCandidate> in_reach;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dx = -1; dx <= 1; ++dx) {
        const auto it = by_group_.find({own[0] + dx, own[1] + dy, own[2] + dz});
        if (it != by_group_.end()) in_reach.insert(in_reach.end(), it->second.begin(), it->second.end());
      }
    }
  }
  return nearest_references(cell, in_reach, grid_spacing);
}

std::vector<uint32_t> nearest_references(const CellIndex& cell, const std::vector<ReferenceCandidate>& candidates,
                                         const std::array<double, 3>& grid_spacing) {
  const std::array<double, 3> here = as_point(cell);
  std::vector<Ranked> ranked;
  ranked.reserve(candidates.size());
  for (const ReferenceCandidate& candidate : candidates) {
    ranked.push_back({distance_squared(here, candidate.index, grid_spacing), candidate.index, candidate.id});
  }
  // Selection by linear scans rather than a sort: the tolerant comparison is not a
  // strict weak order, and a scan stays well defined with it.
  std::vector<uint32_t> nearest;
  for (int pick = 0; pick < 2 && !ranked.empty(); ++pick) {
    size_t best = 0;
    for (size_t i = 1; i < ranked.size(); ++i) {
      if (ranks_before(ranked[i], ranked[best])) best = i;
    }
    nearest.push_back(ranked[best].ordinal);
    ranked.erase(ranked.begin() + static_cast<std::ptrdiff_t>(best));
  }
  return nearest;
}

}  // namespace svc
