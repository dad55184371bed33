// SPDX-License-Identifier: BSD-2-Clause
#include "spatial/placement.h"

#include "spatial/visibility.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <optional>
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

bool index_less(const CellIndex& a, const CellIndex& b) {
  if (a.y != b.y) return a.y < b.y;
  if (a.z != b.z) return a.z < b.z;
  return a.x < b.x;
}

// The ids of all candidates in the order of the References rule, nearest first.
// Selection by linear scans rather than a sort: the tolerant comparison is not a strict
// weak order, and a scan stays well defined with it.
std::vector<uint32_t> distance_order(const CellIndex& cell, const std::vector<ReferenceCandidate>& candidates,
                                     const std::array<double, 3>& grid_spacing) {
  const std::array<double, 3> here = as_point(cell);
  std::vector<Ranked> ranked;
  ranked.reserve(candidates.size());
  for (const ReferenceCandidate& candidate : candidates) {
    ranked.push_back({distance_squared(here, candidate.index, grid_spacing), candidate.index, candidate.id});
  }
  std::vector<uint32_t> order;
  while (!ranked.empty()) {
    size_t best = 0;
    for (size_t i = 1; i < ranked.size(); ++i) {
      if (ranks_before(ranked[i], ranked[best])) best = i;
    }
    order.push_back(ranked[best].ordinal);
    ranked.erase(ranked.begin() + static_cast<std::ptrdiff_t>(best));
  }
  return order;
}

// Per cell the other cells in its reach (own and adjacent groups), in (y, z, x) order so
// that sums over them do not depend on the order of `cells`. Reach is symmetric.
std::vector<std::vector<uint32_t>> reach_lists(const std::vector<CellIndex>& cells,
                                               const std::array<int32_t, 3>& i_spacing) {
  ReachIndex index(i_spacing);
  for (uint32_t ordinal = 0; ordinal < cells.size(); ++ordinal) index.add({cells[ordinal], ordinal});
  std::vector<std::vector<uint32_t>> lists(cells.size());
  for (uint32_t ordinal = 0; ordinal < cells.size(); ++ordinal) {
    for (const ReferenceCandidate& other : index.in_reach(cells[ordinal])) {
      if (other.id != ordinal) lists[ordinal].push_back(other.id);
    }
    std::sort(lists[ordinal].begin(), lists[ordinal].end(),
              [&](uint32_t a, uint32_t b) { return index_less(cells[a], cells[b]); });
  }
  return lists;
}

Status missing_pair(const std::vector<CellIndex>& cells, uint32_t cell, uint32_t reference) {
  return Status(ErrorCode::kInvalidArgument, "placement: the visibility table lacks what cell " +
                                                 index_text(cells[reference]) + " sees of cell " +
                                                 index_text(cells[cell]));
}

Result<std::vector<uint32_t>> references_by_visibility(const std::vector<CellIndex>& cells, uint32_t ordinal,
                                                       const ReachIndex& reach,
                                                       const std::array<double, 3>& grid_spacing,
                                                       const VisibilityTable& table) {
  const std::vector<ReferenceCandidate> candidates = reach.in_reach(cells[ordinal]);
  for (const ReferenceCandidate& candidate : candidates) {
    if (!table.has(ordinal, candidate.id)) return missing_pair(cells, ordinal, candidate.id);
  }
  return visible_references(cells[ordinal], candidates, grid_spacing, [&](uint32_t first, uint32_t second) {
    return table.seen_by_either(ordinal, first, second);
  });
}

// The greedy part of the visibility layout (placement.h, place_cubes).
class CostPlacement {
 public:
  CostPlacement(const std::vector<CellIndex>& cells, const std::array<int32_t, 3>& i_spacing,
                const LayoutCosts& costs, const VisibilityTable& table, std::vector<CellPlacement>* placement)
      : cells_(cells),
        costs_(costs),
        table_(table),
        placement_(*placement),
        reach_(reach_lists(cells, i_spacing)) {}

  // Lattice I-cubes' pairs; and which B-cubes have all their pairs, so may be added.
  Status prepare() {
    candidate_.assign(cells_.size(), 1);
    for (uint32_t c = 0; c < cells_.size(); ++c) {
      for (uint32_t k : reach_[c]) {
        if (table_.has(c, k)) continue;
        if (placement_[k].intra) return missing_pair(cells_, c, k);
        candidate_[k] = 0;
      }
    }
    best_.assign(cells_.size(), 0);
    for (uint32_t c = 0; c < cells_.size(); ++c) best_[c] = best_pair_seen(c);
    return Status::Ok();
  }

  // B-cubes whose change could pay if it made every B-cube in reach seen whole.
  std::vector<uint32_t> may_pay() const {
    std::vector<uint32_t> found;
    for (uint32_t k = 0; k < cells_.size(); ++k) {
      if (placement_[k].intra) continue;
      double most_saved = 0;
      for (uint32_t c : reach_[k]) {
        if (!placement_[c].intra) most_saved += b_cost(c, best_[c]) - costs_.seen_b_face;
      }
      if (most_saved > 1.0 - b_cost(k, best_[k]) + kMinGain) found.push_back(k);
    }
    return found;
  }

  Status run() {
    SVC_RETURN_IF_ERROR(prepare());
    for (;;) {
      double best_change = 0;
      int64_t chosen = -1;
      for (uint32_t k = 0; k < cells_.size(); ++k) {
        if (placement_[k].intra || !candidate_[k]) continue;
        const double change = change_if_intra(k);
        if (!(change < -kMinGain)) continue;
        if (chosen < 0 || change < best_change - kMinGain ||
            (change <= best_change + kMinGain && index_less(cells_[k], cells_[static_cast<size_t>(chosen)]))) {
          best_change = change;
          chosen = k;
        }
      }
      if (chosen < 0) return Status::Ok();
      const uint32_t k = static_cast<uint32_t>(chosen);
      for (uint32_t c : reach_[k]) {
        if (!placement_[c].intra) best_[c] = seen_with(c, k);
      }
      placement_[k].intra = true;
    }
  }

 private:
  // Additions must lower the cost by more than rounding could.
  static constexpr double kMinGain = 1e-9;

  double share(uint32_t cell, size_t seen) const {
    const size_t samples = table_.samples(cell);
    return samples == 0 ? 1.0 : static_cast<double>(seen) / static_cast<double>(samples);
  }
  double b_cost(uint32_t cell, size_t seen) const {
    const double s = share(cell, seen);
    return costs_.seen_b_face * s + costs_.unseen_b_face * (1.0 - s);
  }

  // Most samples of B-cube `c` a pair (or one) of the I-cubes in its reach sees.
  size_t best_pair_seen(uint32_t c) const {
    size_t best = 0;
    const std::vector<uint32_t>& near = reach_[c];
    for (size_t a = 0; a < near.size(); ++a) {
      if (!placement_[near[a]].intra) continue;
      best = std::max(best, table_.seen_by_either(c, near[a], near[a]));
      for (size_t b = a + 1; b < near.size(); ++b) {
        if (placement_[near[b]].intra) best = std::max(best, table_.seen_by_either(c, near[a], near[b]));
      }
    }
    return best;
  }

  // best_pair_seen of `c` once `k` (in its reach) is an I-cube too.
  size_t seen_with(uint32_t c, uint32_t k) const {
    size_t best = std::max(best_[c], table_.seen_by_either(c, k, k));
    for (uint32_t j : reach_[c]) {
      if (placement_[j].intra) best = std::max(best, table_.seen_by_either(c, k, j));
    }
    return best;
  }

  // Change of the estimated cost (in I-faces per face direction) if B-cube k became an
  // I-cube.
  double change_if_intra(uint32_t k) const {
    double change = 1.0 - b_cost(k, best_[k]);
    for (uint32_t c : reach_[k]) {
      if (placement_[c].intra) continue;
      change += b_cost(c, seen_with(c, k)) - b_cost(c, best_[c]);
    }
    return change;
  }

  const std::vector<CellIndex>& cells_;
  const LayoutCosts& costs_;
  const VisibilityTable& table_;
  std::vector<CellPlacement>& placement_;
  const std::vector<std::vector<uint32_t>> reach_;
  std::vector<size_t> best_;
  std::vector<uint8_t> candidate_;
};

Status add_intra_by_cost(const std::vector<CellIndex>& cells, const std::array<int32_t, 3>& i_spacing,
                         const LayoutCosts& costs, const VisibilityTable& table,
                         std::vector<CellPlacement>* placement) {
  return CostPlacement(cells, i_spacing, costs, table, placement).run();
}

}  // namespace

Result<std::vector<CellPlacement>> place_cubes(const std::vector<CellIndex>& cells,
                                               const std::array<int32_t, 3>& dims,
                                               const PlacementSettings& settings,
                                               const std::array<double, 3>& grid_spacing) {
  return place_cubes(cells, dims, settings, grid_spacing, nullptr);
}

Result<std::vector<CellPlacement>> place_cubes(const std::vector<CellIndex>& cells,
                                               const std::array<int32_t, 3>& dims,
                                               const PlacementSettings& settings,
                                               const std::array<double, 3>& grid_spacing,
                                               const VisibilityTable* visibility) {
  SVC_RETURN_IF_ERROR(validate(cells, dims, settings, grid_spacing));
  const bool needs_visibility = settings.layout == Layout::kVisibility || settings.visibility_references;
  if (needs_visibility && (visibility == nullptr || visibility->cells() != cells.size())) {
    return Status(ErrorCode::kInvalidArgument,
                  "placement: the visibility layout and references need a visibility table of every cell");
  }
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

  if (settings.layout == Layout::kVisibility) {
    SVC_RETURN_IF_ERROR(add_intra_by_cost(cells, s, settings.costs, *visibility, &placement));
  }

  // References: among the I-cubes of the own and adjacent groups, the nearest two or the
  // two that see most.
  ReachIndex reach(s);
  for (uint32_t ordinal = 0; ordinal < cells.size(); ++ordinal) {
    if (placement[ordinal].intra) reach.add({cells[ordinal], ordinal});
  }
  for (uint32_t ordinal = 0; ordinal < cells.size(); ++ordinal) {
    if (placement[ordinal].intra) continue;
    const CellIndex& c = cells[ordinal];
    auto& refs = placement[ordinal].references;
    if (settings.visibility_references) {
      SVC_ASSIGN_OR_RETURN(refs, references_by_visibility(cells, ordinal, reach, grid_spacing, *visibility));
    } else {
      refs = reach.references(c, grid_spacing);
    }
    if (refs.empty()) {
      return Status(ErrorCode::kInternal, "placement: B-cube " + index_text(c) + " has no I-cube in its own group");
    }
  }
  return placement;
}

Result<std::vector<uint32_t>> layout_candidates(const std::vector<CellIndex>& cells,
                                                const std::array<int32_t, 3>& dims,
                                                const PlacementSettings& settings,
                                                const std::array<double, 3>& grid_spacing,
                                                const VisibilityTable& visibility) {
  PlacementSettings lattice = settings;
  lattice.layout = Layout::kRegular;
  lattice.visibility_references = false;
  SVC_ASSIGN_OR_RETURN(std::vector<CellPlacement> placement, place_cubes(cells, dims, lattice, grid_spacing));
  if (visibility.cells() != cells.size()) {
    return Status(ErrorCode::kInvalidArgument, "placement: the visibility table does not cover every cell");
  }
  CostPlacement cost(cells, settings.i_spacing, settings.costs, visibility, &placement);
  SVC_RETURN_IF_ERROR(cost.prepare());
  return cost.may_pay();
}

Result<std::vector<CellPlacement>> place_cubes(const std::vector<CellIndex>& cells,
                                               const std::array<int32_t, 3>& dims,
                                               const PlacementSettings& settings) {
  return place_cubes(cells, dims, settings, {1.0, 1.0, 1.0});
}

void VisibilityTable::set_seen(uint32_t cell, const std::vector<std::pair<uint32_t, std::vector<uint64_t>>>& seen) {
  std::vector<size_t> order(seen.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return seen[a].first < seen[b].first; });
  CellSeen& entry = seen_.at(cell);
  entry.references.clear();
  entry.counts.clear();
  for (size_t i = 0; i < order.size(); ++i) {
    entry.references.push_back(seen[order[i]].first);
    for (size_t j = i; j < order.size(); ++j) {
      const size_t count = count_seen_by_either(seen[order[i]].second, seen[order[j]].second);
      entry.counts.push_back(static_cast<uint32_t>(count));
    }
  }
  entry.references.shrink_to_fit();
  entry.counts.shrink_to_fit();
}

bool VisibilityTable::has(uint32_t cell, uint32_t reference) const {
  if (cell >= seen_.size()) return false;
  const std::vector<uint32_t>& references = seen_[cell].references;
  return std::binary_search(references.begin(), references.end(), reference);
}

size_t VisibilityTable::seen_by_either(uint32_t cell, uint32_t first, uint32_t second) const {
  if (cell >= seen_.size()) return 0;
  const CellSeen& entry = seen_[cell];
  const auto position = [&](uint32_t reference) -> std::optional<size_t> {
    const auto it = std::lower_bound(entry.references.begin(), entry.references.end(), reference);
    if (it == entry.references.end() || *it != reference) return std::nullopt;
    return static_cast<size_t>(it - entry.references.begin());
  };
  std::optional<size_t> i = position(first), j = position(second);
  if (!i || !j) return 0;
  if (*i > *j) std::swap(i, j);
  // Row i of the upper triangle starts after the rows before it: n + (n-1) + ... entries.
  const size_t n = entry.references.size();
  const size_t row_start = *i * n - *i * (*i - 1) / 2;
  return entry.counts[row_start + (*j - *i)];
}

Result<std::vector<std::pair<uint32_t, uint32_t>>> reach_pairs(const std::vector<CellIndex>& cells,
                                                               const std::array<int32_t, 3>& i_spacing) {
  PlacementSettings settings;
  settings.i_spacing = i_spacing;
  std::array<int32_t, 3> dims{1, 1, 1};
  for (const CellIndex& c : cells) {
    if (c.x < 0 || c.y < 0 || c.z < 0) {
      return Status(ErrorCode::kInvalidArgument, "placement: cell " + index_text(c) + " has a negative index");
    }
    dims = {std::max(dims[0], c.x + 1), std::max(dims[1], c.y + 1), std::max(dims[2], c.z + 1)};
  }
  SVC_RETURN_IF_ERROR(validate(cells, dims, settings, {1.0, 1.0, 1.0}));
  const std::vector<std::vector<uint32_t>> lists = reach_lists(cells, i_spacing);
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (uint32_t c = 0; c < cells.size(); ++c) {
    for (uint32_t k : lists[c]) pairs.emplace_back(c, k);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

void ReachIndex::add(const ReferenceCandidate& candidate) {
  const CellIndex& c = candidate.index;
  by_group_[{c.x / spacing_[0], c.y / spacing_[1], c.z / spacing_[2]}].push_back(candidate);
}

std::vector<ReferenceCandidate> ReachIndex::in_reach(const CellIndex& cell) const {
  const GroupKey own = {cell.x / spacing_[0], cell.y / spacing_[1], cell.z / spacing_[2]};
  std::vector<ReferenceCandidate> found;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dx = -1; dx <= 1; ++dx) {
        const auto it = by_group_.find({own[0] + dx, own[1] + dy, own[2] + dz});
        if (it != by_group_.end()) found.insert(found.end(), it->second.begin(), it->second.end());
      }
    }
  }
  return found;
}

std::vector<uint32_t> ReachIndex::references(const CellIndex& cell,
                                             const std::array<double, 3>& grid_spacing) const {
  return nearest_references(cell, in_reach(cell), grid_spacing);
}

std::vector<uint32_t> nearest_references(const CellIndex& cell, const std::vector<ReferenceCandidate>& candidates,
                                         const std::array<double, 3>& grid_spacing) {
  std::vector<uint32_t> ranked = distance_order(cell, candidates, grid_spacing);
  if (ranked.size() > 2) ranked.resize(2);
  return ranked;
}

std::vector<uint32_t> visible_references(const CellIndex& cell, const std::vector<ReferenceCandidate>& candidates,
                                         const std::array<double, 3>& grid_spacing, const SeenByEither& seen) {
  const std::vector<uint32_t> ranked = distance_order(cell, candidates, grid_spacing);
  if (ranked.size() <= 1) return ranked;
  size_t best_first = 0, best_second = 1, best_seen = 0;
  bool have_best = false;
  for (size_t first = 0; first < ranked.size(); ++first) {
    for (size_t second = first + 1; second < ranked.size(); ++second) {
      const size_t together = seen(ranked[first], ranked[second]);
      if (!have_best || together > best_seen) {
        best_first = first;
        best_second = second;
        best_seen = together;
        have_best = true;
      }
    }
  }
  return {ranked[best_first], ranked[best_second]};
}

}  // namespace svc
