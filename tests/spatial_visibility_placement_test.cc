// SPDX-License-Identifier: BSD-2-Clause
// Reference choice and I-cube placement by what references see, on hand-made visibility
// tables (the measurement itself: spatial_visibility_test.cc, svc_visibility_test.cc).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <tuple>

#include "spatial/placement.h"
#include "spatial/visibility.h"

namespace svc {
namespace {

constexpr size_t kSamples = 128;  // sample points per cell in these tables

// The layout's settings with the costs these tests count with.
PlacementSettings visibility_settings(bool references = true) {
  PlacementSettings settings;
  settings.layout = Layout::kVisibility;
  settings.visibility_references = references;
  settings.costs = {0.3, 1.0};
  return settings;
}

std::vector<uint64_t> bits(size_t first, size_t end) {
  std::vector<uint64_t> out((kSamples + 63) / 64, 0);
  for (size_t k = first; k < end && k < kSamples; ++k) out[k / 64] |= uint64_t{1} << (k % 64);
  return out;
}

// What candidates see of one cell, as visible_references asks it, from their bitsets.
SeenByEither either(const std::map<uint32_t, std::vector<uint64_t>>& seen) {
  return [&seen](uint32_t first, uint32_t second) { return count_seen_by_either(seen.at(first), seen.at(second)); };
}

std::vector<CellIndex> grid_3x3() {
  std::vector<CellIndex> cells;
  for (int z = 0; z < 3; ++z)
    for (int x = 0; x < 3; ++x) cells.push_back({x, 0, z});
  return cells;
}

size_t ordinal_of(const std::vector<CellIndex>& cells, CellIndex c) {
  return static_cast<size_t>(std::find(cells.begin(), cells.end(), c) - cells.begin());
}

// A table where every cell sees all of every other, except what `hidden` lists:
// (seer, seen) -> the samples it sees instead.
using Key = std::tuple<int, int, int>;
// Only the pairs whose reference `keep` accepts are set.
VisibilityTable table_for(
    const std::vector<CellIndex>& cells, const std::array<int32_t, 3>& spacing,
    const std::map<std::pair<Key, Key>, std::vector<uint64_t>>& hidden,
    const std::function<bool(uint32_t)>& keep = [](uint32_t) { return true; }) {
  VisibilityTable table(cells.size());
  for (uint32_t c = 0; c < cells.size(); ++c) table.set_samples(c, kSamples);
  auto pairs = reach_pairs(cells, spacing);
  EXPECT_TRUE(pairs.ok());
  std::map<uint32_t, std::vector<std::pair<uint32_t, std::vector<uint64_t>>>> by_cell;
  for (const auto& [cell, reference] : *pairs) {
    if (!keep(reference)) continue;
    const Key seen{cells[cell].x, cells[cell].y, cells[cell].z};
    const Key seer{cells[reference].x, cells[reference].y, cells[reference].z};
    const auto it = hidden.find({seer, seen});
    by_cell[cell].emplace_back(reference, it == hidden.end() ? bits(0, kSamples) : it->second);
  }
  for (const auto& [cell, seen] : by_cell) table.set_seen(cell, seen);
  return table;
}

TEST(VisibilityReferences, PairThatSeesMostWinsOverTheNearest) {
  const std::vector<ReferenceCandidate> candidates = {{{1, 0, 0}, 10}, {{2, 0, 0}, 20}, {{5, 0, 0}, 30}};
  // The nearest two see the same half; the farthest sees the other half.
  std::map<uint32_t, std::vector<uint64_t>> seen = {{10, bits(0, 64)}, {20, bits(0, 64)}, {30, bits(64, 128)}};
  auto refs = visible_references({0, 0, 0}, candidates, {1, 1, 1}, either(seen));
  EXPECT_EQ(refs, (std::vector<uint32_t>{10, 30}));  // nearest first
}

TEST(VisibilityReferences, EqualCoverageKeepsTheNearestTwo) {
  const std::vector<ReferenceCandidate> candidates = {{{4, 0, 0}, 1}, {{1, 0, 0}, 2}, {{2, 0, 0}, 3}};
  std::map<uint32_t, std::vector<uint64_t>> seen = {{1, bits(0, 128)}, {2, bits(0, 128)}, {3, bits(0, 128)}};
  auto refs = visible_references({0, 0, 0}, candidates, {1, 1, 1}, either(seen));
  EXPECT_EQ(refs, (std::vector<uint32_t>{2, 3}));
  EXPECT_EQ(refs, nearest_references({0, 0, 0}, candidates, {1, 1, 1}));
}

TEST(VisibilityReferences, OneCandidateIsTheOnlyReference) {
  const std::vector<ReferenceCandidate> candidates = {{{4, 0, 0}, 7}};
  const std::vector<uint64_t> none = bits(0, 0);
  auto refs = visible_references({0, 0, 0}, candidates, {1, 1, 1},
                                 [&](uint32_t, uint32_t) { return count_seen_by_either(none, none); });
  EXPECT_EQ(refs, (std::vector<uint32_t>{7}));
}

TEST(VisibilityPlacement, CellHiddenFromTheCentreGetsItsOwnIntraCubeWhenThatPays) {
  const std::vector<CellIndex> cells = grid_3x3();
  // Only (0,0,0) and (1,0,0) see each other; no other cell sees anything of them.
  std::map<std::pair<Key, Key>, std::vector<uint64_t>> hidden;
  for (const CellIndex& c : cells) {
    if (c.z == 0 && c.x < 2) continue;
    hidden[{Key{c.x, c.y, c.z}, Key{0, 0, 0}}] = bits(0, 0);
    hidden[{Key{c.x, c.y, c.z}, Key{1, 0, 0}}] = bits(0, 0);
  }
  const VisibilityTable table = table_for(cells, {3, 1, 3}, hidden);
  const PlacementSettings settings = visibility_settings();
  auto placement = place_cubes(cells, {3, 1, 3}, settings, {1, 1, 1}, &table);
  ASSERT_TRUE(placement.ok()) << placement.status().to_string();
  std::vector<CellIndex> intra;
  for (size_t c = 0; c < cells.size(); ++c) {
    if ((*placement)[c].intra) intra.push_back(cells[c]);
  }
  // Either hidden cell as an I-cube serves the other (cost 1 + 0.3 against 2 x 1.0); of
  // the two, the smaller (y, z, x) index. A second one would not pay (1 against 0.3).
  EXPECT_EQ(intra, (std::vector<CellIndex>{{0, 0, 0}, {1, 0, 1}}));
  const auto& refs = (*placement)[ordinal_of(cells, {1, 0, 0})].references;
  ASSERT_FALSE(refs.empty());
  EXPECT_EQ(cells[refs[0]], (CellIndex{0, 0, 0}));
  for (const CellPlacement& p : *placement) EXPECT_LE(p.references.size(), 2u);
}

TEST(VisibilityPlacement, NoIntraCubeIsAddedWhenReferencesSeeEverything) {
  const std::vector<CellIndex> cells = grid_3x3();
  const VisibilityTable table = table_for(cells, {3, 1, 3}, {});
  const PlacementSettings settings = visibility_settings();
  auto visible = place_cubes(cells, {3, 1, 3}, settings, {1, 1, 1}, &table);
  auto regular = place_cubes(cells, {3, 1, 3}, PlacementSettings{}, {1, 1, 1});
  ASSERT_TRUE(visible.ok() && regular.ok());
  for (size_t c = 0; c < cells.size(); ++c) {
    EXPECT_EQ((*visible)[c].intra, (*regular)[c].intra);
    EXPECT_EQ((*visible)[c].references, (*regular)[c].references);
  }
}

TEST(VisibilityPlacement, AdditionStopsWhenItNoLongerPays) {
  const std::vector<CellIndex> cells = grid_3x3();
  // One hidden cell that no other cell would serve: 1 (an I-cube) against 1.0 (a B-cube
  // no reference sees) does not pay.
  std::map<std::pair<Key, Key>, std::vector<uint64_t>> hidden;
  for (const CellIndex& c : cells) hidden[{Key{c.x, c.y, c.z}, Key{2, 0, 2}}] = bits(0, 0);
  const VisibilityTable table = table_for(cells, {3, 1, 3}, hidden);
  const PlacementSettings settings = visibility_settings(false);
  auto placement = place_cubes(cells, {3, 1, 3}, settings, {1, 1, 1}, &table);
  ASSERT_TRUE(placement.ok());
  EXPECT_FALSE((*placement)[ordinal_of(cells, {2, 0, 2})].intra);
  size_t intra = 0;
  for (const CellPlacement& p : *placement) intra += p.intra ? 1 : 0;
  EXPECT_EQ(intra, 1u);
}

TEST(VisibilityPlacement, ResultDoesNotDependOnCellOrder) {
  std::vector<CellIndex> cells;
  for (int z = 0; z < 6; ++z)
    for (int x = 0; x < 6; ++x) cells.push_back({x, 0, z});
  // Cells of column x = 0 hide from everything but each other.
  auto hidden_map = [](const std::vector<CellIndex>& list) {
    std::map<std::pair<Key, Key>, std::vector<uint64_t>> hidden;
    for (const CellIndex& seen : list)
      for (const CellIndex& seer : list)
        if ((seen.x == 0) != (seer.x == 0)) hidden[{Key{seer.x, 0, seer.z}, Key{seen.x, 0, seen.z}}] = bits(0, 16);
    return hidden;
  };
  const PlacementSettings settings = visibility_settings();
  std::vector<CellIndex> reversed(cells.rbegin(), cells.rend());
  const VisibilityTable forward_table = table_for(cells, {3, 1, 3}, hidden_map(cells));
  const VisibilityTable reversed_table = table_for(reversed, {3, 1, 3}, hidden_map(reversed));
  auto forward = place_cubes(cells, {6, 1, 6}, settings, {1, 1, 1}, &forward_table);
  auto backward = place_cubes(reversed, {6, 1, 6}, settings, {1, 1, 1}, &reversed_table);
  ASSERT_TRUE(forward.ok() && backward.ok());
  size_t added = 0;
  for (size_t c = 0; c < cells.size(); ++c) {
    const CellPlacement& a = (*forward)[c];
    const CellPlacement& b = (*backward)[ordinal_of(reversed, cells[c])];
    EXPECT_EQ(a.intra, b.intra);
    ASSERT_EQ(a.references.size(), b.references.size());
    for (size_t r = 0; r < a.references.size(); ++r) EXPECT_EQ(cells[a.references[r]], reversed[b.references[r]]);
    added += a.intra ? 1 : 0;
  }
  EXPECT_EQ(added, 5u);  // the lattice's four and one that serves the column
}

TEST(VisibilityPlacement, CandidatePairsAloneGiveTheSamePlacement) {
  std::vector<CellIndex> cells;
  for (int z = 0; z < 6; ++z)
    for (int x = 0; x < 12; ++x) cells.push_back({x, 0, z});
  std::map<std::pair<Key, Key>, std::vector<uint64_t>> hidden;
  for (const CellIndex& seen : cells)
    for (const CellIndex& seer : cells)
      if ((seen.x == 0) != (seer.x == 0)) hidden[{Key{seer.x, 0, seer.z}, Key{seen.x, 0, seen.z}}] = bits(0, 16);
  const VisibilityTable full = table_for(cells, {3, 1, 3}, hidden);
  const PlacementSettings settings = visibility_settings();
  auto lattice = place_cubes(cells, {12, 1, 6}, PlacementSettings{}, {1, 1, 1});
  ASSERT_TRUE(lattice.ok());
  const VisibilityTable lattice_only =
      table_for(cells, {3, 1, 3}, hidden, [&](uint32_t k) { return (*lattice)[k].intra; });
  auto candidates = layout_candidates(cells, {12, 1, 6}, settings, {1, 1, 1}, lattice_only);
  ASSERT_TRUE(candidates.ok()) << candidates.status().to_string();
  // Cells out of reach of the hidden column (x >= 6) could never pay: every cell they
  // reach is seen whole already.
  ASSERT_FALSE(candidates->empty());
  for (uint32_t k : *candidates) EXPECT_LT(cells[k].x, 6) << k;
  const VisibilityTable partial = table_for(cells, {3, 1, 3}, hidden, [&](uint32_t k) {
    return (*lattice)[k].intra || std::count(candidates->begin(), candidates->end(), k) > 0;
  });
  auto from_full = place_cubes(cells, {12, 1, 6}, settings, {1, 1, 1}, &full);
  auto from_partial = place_cubes(cells, {12, 1, 6}, settings, {1, 1, 1}, &partial);
  ASSERT_TRUE(from_full.ok() && from_partial.ok());
  size_t intra = 0;
  for (size_t c = 0; c < cells.size(); ++c) {
    EXPECT_EQ((*from_full)[c].intra, (*from_partial)[c].intra);
    EXPECT_EQ((*from_full)[c].references, (*from_partial)[c].references);
    intra += (*from_full)[c].intra ? 1 : 0;
  }
  EXPECT_EQ(intra, 9u);  // the lattice's eight and one for the column
}

TEST(VisibilityPlacement, MissingTableIsAnError) {
  const std::vector<CellIndex> cells = grid_3x3();
  PlacementSettings settings;
  settings.visibility_references = true;
  auto none = place_cubes(cells, {3, 1, 3}, settings, {1, 1, 1}, nullptr);
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.status().code(), ErrorCode::kInvalidArgument);
  VisibilityTable partial(cells.size());
  auto lacking = place_cubes(cells, {3, 1, 3}, settings, {1, 1, 1}, &partial);
  ASSERT_FALSE(lacking.ok());
  EXPECT_NE(lacking.status().message().find("cell (1, 0, 1) sees of cell (0, 0, 0)"), std::string::npos)
      << lacking.status().message();
}

TEST(VisibilityPlacement, ReachPairsListEveryOtherCellInReach) {
  std::vector<CellIndex> cells;
  for (int x = 0; x < 9; ++x) cells.push_back({x, 0, 0});
  auto pairs = reach_pairs(cells, {3, 1, 3});
  ASSERT_TRUE(pairs.ok());
  // Cells of group 0 reach groups 0 and 1 (5 others), group 1 all (8), group 2 groups 1, 2.
  EXPECT_EQ(pairs->size(), 3u * 5 + 3u * 8 + 3u * 5);
  for (const auto& [cell, reference] : *pairs) {
    EXPECT_NE(cell, reference);
    EXPECT_LE(std::abs(cells[cell].x / 3 - cells[reference].x / 3), 1);
  }
}

}  // namespace
}  // namespace svc
