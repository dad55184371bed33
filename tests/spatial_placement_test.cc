// SPDX-License-Identifier: BSD-2-Clause
#include "spatial/placement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>

namespace svc {
namespace {

using Key = std::tuple<int, int, int>;  // (x, y, z)

Key key_of(const CellIndex& c) { return {c.x, c.y, c.z}; }

std::vector<CellIndex> full_grid(int nx, int ny, int nz) {
  std::vector<CellIndex> cells;
  for (int y = 0; y < ny; ++y)
    for (int z = 0; z < nz; ++z)
      for (int x = 0; x < nx; ++x) cells.push_back({x, y, z});
  return cells;
}

std::vector<CellPlacement> place(const std::vector<CellIndex>& cells, std::array<int32_t, 3> dims,
                                 std::array<int32_t, 3> spacing = {3, 1, 3},
                                 std::array<double, 3> grid_spacing = {1, 1, 1}) {
  PlacementSettings settings;
  settings.i_spacing = spacing;
  auto result = place_cubes(cells, dims, settings, grid_spacing);
  EXPECT_TRUE(result.ok()) << result.status().to_string();
  return result.ok() ? *result : std::vector<CellPlacement>{};
}

size_t ordinal_of(const std::vector<CellIndex>& cells, CellIndex c) {
  return static_cast<size_t>(std::find(cells.begin(), cells.end(), c) - cells.begin());
}

// References as cell indices, for readable expectations.
std::vector<Key> refs_of(const std::vector<CellIndex>& cells, const std::vector<CellPlacement>& placement,
                         CellIndex c) {
  std::vector<Key> out;
  for (uint32_t r : placement[ordinal_of(cells, c)].references) out.push_back(key_of(cells[r]));
  return out;
}

double dist2(const CellIndex& a, const CellIndex& b) {
  const double dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
  return dx * dx + dy * dy + dz * dz;
}

// Structural invariants every placement must satisfy.
void expect_decodable(const std::vector<CellIndex>& cells, const std::vector<CellPlacement>& placement) {
  ASSERT_EQ(placement.size(), cells.size());
  for (size_t i = 0; i < cells.size(); ++i) {
    const auto& p = placement[i];
    if (p.intra) {
      EXPECT_TRUE(p.references.empty());
      continue;
    }
    ASSERT_GE(p.references.size(), 1u);
    ASSERT_LE(p.references.size(), 2u);
    for (uint32_t r : p.references) {
      ASSERT_LT(r, cells.size());
      EXPECT_TRUE(placement[r].intra) << "a B-cube references a B-cube";
    }
    if (p.references.size() == 2) {
      EXPECT_NE(p.references[0], p.references[1]);
      EXPECT_LE(dist2(cells[i], cells[p.references[0]]), dist2(cells[i], cells[p.references[1]]));
    }
  }
}

TEST(SpatialPlacement, DefaultPutsIntraAtCentreOfEach3x3Group) {
  const auto cells = full_grid(9, 1, 9);
  const auto placement = place(cells, {9, 1, 9});
  expect_decodable(cells, placement);
  std::vector<Key> intra;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (placement[i].intra) intra.push_back(key_of(cells[i]));
  }
  std::sort(intra.begin(), intra.end());
  std::vector<Key> expected;
  for (int x : {1, 4, 7})
    for (int z : {1, 4, 7}) expected.push_back({x, 0, z});
  EXPECT_EQ(intra, expected);

  // Every B-cube has two references, the two nearest I-cubes of the whole grid.
  for (size_t i = 0; i < cells.size(); ++i) {
    if (placement[i].intra) continue;
    ASSERT_EQ(placement[i].references.size(), 2u) << "cell " << i;
    const double d0 = dist2(cells[i], cells[placement[i].references[0]]);
    const double d1 = dist2(cells[i], cells[placement[i].references[1]]);
    for (size_t k = 0; k < cells.size(); ++k) {
      if (!placement[k].intra || k == placement[i].references[0] || k == placement[i].references[1]) {
        continue;
      }
      EXPECT_GE(dist2(cells[i], cells[k]), d1);
    }
    EXPECT_LE(d0, 2.0);  // the own group's centre is at most one diagonal step away
  }
}

TEST(SpatialPlacement, EqualDistancesResolveBySmallestYZX) {
  const auto cells = full_grid(9, 1, 9);
  const auto placement = place(cells, {9, 1, 9});
  // (4,0,1) and (1,0,4) are equally far from (0,0,0): smaller z wins.
  EXPECT_EQ(refs_of(cells, placement, {0, 0, 0}), (std::vector<Key>{{1, 0, 1}, {4, 0, 1}}));
  // From (2,0,2): (4,0,1) and (1,0,4) again tie at distance sqrt(5).
  EXPECT_EQ(refs_of(cells, placement, {2, 0, 2}), (std::vector<Key>{{1, 0, 1}, {4, 0, 1}}));
  // From (3,0,3): (4,0,4) nearest; (4,0,1), (1,0,4) tie; z decides.
  EXPECT_EQ(refs_of(cells, placement, {3, 0, 3}), (std::vector<Key>{{4, 0, 4}, {4, 0, 1}}));
}

TEST(SpatialPlacement, TwoLayersReferenceTheIntraCubeAboveWhenNearer) {
  const auto cells = full_grid(9, 2, 9);
  const auto placement = place(cells, {9, 2, 9});
  expect_decodable(cells, placement);
  EXPECT_EQ(refs_of(cells, placement, {0, 0, 0}), (std::vector<Key>{{1, 0, 1}, {1, 1, 1}}));
  EXPECT_EQ(refs_of(cells, placement, {1, 0, 0}), (std::vector<Key>{{1, 0, 1}, {1, 1, 1}}));
}

TEST(SpatialPlacement, GridSpacingMeasuresDistanceBetweenCellCentres) {
  const auto cells = full_grid(9, 1, 9);
  // Unit spacing: from (0,0,2), (1,0,4) (distance^2 5) beats (4,0,1) (17).
  EXPECT_EQ(refs_of(cells, place(cells, {9, 1, 9}), {0, 0, 2}), (std::vector<Key>{{1, 0, 1}, {1, 0, 4}}));
  // Cells ten times closer along x: (4,0,1) is now the nearer one.
  EXPECT_EQ(refs_of(cells, place(cells, {9, 1, 9}, {3, 1, 3}, {0.1, 1, 1}), {0, 0, 2}),
            (std::vector<Key>{{1, 0, 1}, {4, 0, 1}}));
}

TEST(SpatialPlacement, IntraOnlySpacing) {
  const auto cells = full_grid(5, 2, 4);
  const auto placement = place(cells, {5, 2, 4}, {1, 1, 1});
  for (const auto& p : placement) {
    EXPECT_TRUE(p.intra);
    EXPECT_TRUE(p.references.empty());
  }
}

TEST(SpatialPlacement, MissingCentreMovesToNearestPresentCell) {
  auto cells = full_grid(9, 1, 9);
  cells.erase(cells.begin() + static_cast<std::ptrdiff_t>(ordinal_of(cells, {4, 0, 4})));
  const auto placement = place(cells, {9, 1, 9});
  expect_decodable(cells, placement);
  // Four cells at distance 1 from (4,0,4); smallest (y, z, x) is (4,0,3).
  EXPECT_TRUE(placement[ordinal_of(cells, {4, 0, 3})].intra);
  for (CellIndex c : {CellIndex{3, 0, 4}, CellIndex{5, 0, 4}, CellIndex{4, 0, 5}}) {
    EXPECT_FALSE(placement[ordinal_of(cells, c)].intra);
  }
  EXPECT_EQ(std::count_if(placement.begin(), placement.end(), [](const CellPlacement& p) { return p.intra; }), 9);
  EXPECT_EQ(refs_of(cells, placement, {4, 0, 5})[0], (Key{4, 0, 3}));
}

TEST(SpatialPlacement, EmptyGroupHasNoIntraAndIsOutOfReachBeyond) {
  // Cells only in the first and third 3x3 groups of a 9x1x3 row of groups.
  std::vector<CellIndex> cells;
  for (CellIndex c : full_grid(9, 1, 3)) {
    if (c.x < 3 || c.x >= 6) cells.push_back(c);
  }
  const auto placement = place(cells, {9, 1, 3});
  expect_decodable(cells, placement);
  EXPECT_EQ(std::count_if(placement.begin(), placement.end(), [](const CellPlacement& p) { return p.intra; }), 2);
  // Group 2 is not adjacent to group 0: one reference each.
  EXPECT_EQ(refs_of(cells, placement, {2, 0, 1}), (std::vector<Key>{{1, 0, 1}}));
  EXPECT_EQ(refs_of(cells, placement, {6, 0, 1}), (std::vector<Key>{{7, 0, 1}}));
}

TEST(SpatialPlacement, OneRow) {
  const auto cells = full_grid(9, 1, 1);
  const auto placement = place(cells, {9, 1, 1});
  expect_decodable(cells, placement);
  for (int x = 0; x < 9; ++x) {
    EXPECT_EQ(placement[static_cast<size_t>(x)].intra, x == 1 || x == 4 || x == 7) << x;
  }
  EXPECT_EQ(refs_of(cells, placement, {0, 0, 0}), (std::vector<Key>{{1, 0, 0}, {4, 0, 0}}));
  EXPECT_EQ(refs_of(cells, placement, {2, 0, 0}), (std::vector<Key>{{1, 0, 0}, {4, 0, 0}}));
  EXPECT_EQ(refs_of(cells, placement, {3, 0, 0}), (std::vector<Key>{{4, 0, 0}, {1, 0, 0}}));
  EXPECT_EQ(refs_of(cells, placement, {8, 0, 0}), (std::vector<Key>{{7, 0, 0}, {4, 0, 0}}));
}

TEST(SpatialPlacement, ShortRowHasOneReference) {
  const auto cells = full_grid(3, 1, 1);
  const auto placement = place(cells, {3, 1, 1});
  EXPECT_FALSE(placement[0].intra);
  EXPECT_TRUE(placement[1].intra);
  EXPECT_EQ(placement[0].references, std::vector<uint32_t>{1});
  EXPECT_EQ(placement[2].references, std::vector<uint32_t>{1});
}

TEST(SpatialPlacement, PartialEdgeGroupGetsItsOwnIntraCube) {
  const auto cells = full_grid(10, 1, 1);
  const auto placement = place(cells, {10, 1, 1});
  std::vector<int> intra;
  for (int x = 0; x < 10; ++x) {
    if (placement[static_cast<size_t>(x)].intra) intra.push_back(x);
  }
  EXPECT_EQ(intra, (std::vector<int>{1, 4, 7, 9}));
}

TEST(SpatialPlacement, EvenSpacingTakesUpperMiddleCell) {
  const auto cells = full_grid(6, 1, 4);
  const auto placement = place(cells, {6, 1, 4}, {2, 1, 4});
  std::vector<Key> intra;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (placement[i].intra) intra.push_back(key_of(cells[i]));
  }
  std::sort(intra.begin(), intra.end());
  EXPECT_EQ(intra, (std::vector<Key>{{1, 0, 2}, {3, 0, 2}, {5, 0, 2}}));
}

TEST(SpatialPlacement, SingleCellIsIntra) {
  const auto placement = place({{0, 0, 0}}, {1, 1, 1});
  ASSERT_EQ(placement.size(), 1u);
  EXPECT_TRUE(placement[0].intra);
}

TEST(SpatialPlacement, EmptyCellListIsEmptyPlacement) { EXPECT_TRUE(place({}, {3, 1, 3}).empty()); }

struct RatioCase {
  std::array<int32_t, 3> dims;
  std::array<int32_t, 3> spacing;
  int ratio;
};

TEST(SpatialPlacement, RatioSpacingsGiveTheDocumentedBToIRatio) {
  const RatioCase cases[] = {
      {{18, 1, 18}, {3, 1, 3}, 8},  {{18, 1, 18}, {3, 1, 2}, 5},  {{18, 1, 18}, {2, 1, 3}, 5},
      {{18, 2, 18}, {3, 2, 3}, 17}, {{18, 1, 18}, {6, 1, 3}, 17}, {{9, 3, 9}, {3, 3, 3}, 26},
      {{18, 1, 18}, {9, 1, 3}, 26}, {{6, 2, 6}, {1, 1, 1}, 0},
  };
  for (const auto& c : cases) {
    const auto cells = full_grid(c.dims[0], c.dims[1], c.dims[2]);
    const auto placement = place(cells, c.dims, c.spacing);
    expect_decodable(cells, placement);
    const auto intra =
        std::count_if(placement.begin(), placement.end(), [](const CellPlacement& p) { return p.intra; });
    const auto b = static_cast<long>(cells.size()) - intra;
    EXPECT_EQ(b, c.ratio * intra) << "spacing " << c.spacing[0] << "x" << c.spacing[1] << "x" << c.spacing[2];
  }
}

TEST(SpatialPlacement, ResultDoesNotDependOnInputOrder) {
  std::mt19937 rng(7);
  std::vector<CellIndex> cells;
  for (CellIndex c : full_grid(11, 2, 8)) {
    if (rng() % 4 != 0) cells.push_back(c);  // sparse
  }
  const auto base = place(cells, {11, 2, 8});
  expect_decodable(cells, base);
  auto describe = [](const std::vector<CellIndex>& cs, const std::vector<CellPlacement>& ps) {
    std::map<Key, std::pair<bool, std::vector<Key>>> out;
    for (size_t i = 0; i < cs.size(); ++i) {
      std::vector<Key> refs;
      for (uint32_t r : ps[i].references) refs.push_back(key_of(cs[r]));
      out[key_of(cs[i])] = {ps[i].intra, refs};
    }
    return out;
  };
  const auto expected = describe(cells, base);
  for (int round = 0; round < 3; ++round) {
    auto shuffled = cells;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    const auto placement = place(shuffled, {11, 2, 8});
    EXPECT_EQ(describe(shuffled, placement), expected);
  }
}

TEST(SpatialPlacement, RandomSparseGridsAreAlwaysDecodable) {
  std::mt19937 rng(11);
  for (int round = 0; round < 20; ++round) {
    const std::array<int32_t, 3> dims = {static_cast<int32_t>(1 + rng() % 12), static_cast<int32_t>(1 + rng() % 3),
                                         static_cast<int32_t>(1 + rng() % 12)};
    const std::array<int32_t, 3> spacing = {static_cast<int32_t>(1 + rng() % 5),
                                            static_cast<int32_t>(1 + rng() % 2),
                                            static_cast<int32_t>(1 + rng() % 5)};
    std::vector<CellIndex> cells;
    for (CellIndex c : full_grid(dims[0], dims[1], dims[2])) {
      if (rng() % 3 != 0) cells.push_back(c);
    }
    const auto placement = place(cells, dims, spacing);
    expect_decodable(cells, placement);
    // Exactly one I-cube per non-empty group.
    std::map<Key, int> intra_per_group;
    for (size_t i = 0; i < cells.size(); ++i) {
      const Key group{cells[i].x / spacing[0], cells[i].y / spacing[1], cells[i].z / spacing[2]};
      intra_per_group[group] += placement[i].intra ? 1 : 0;
    }
    for (const auto& [group, count] : intra_per_group) EXPECT_EQ(count, 1);
  }
}

// The reach rule by itself: only I-cubes of the own and adjacent groups count, nearest
// first; with none in reach there is no reference.
TEST(SpatialPlacement, ReachIndexOffersOnlyOwnAndAdjacentGroups) {
  ReachIndex reach({3, 1, 3});
  reach.add({CellIndex{1, 0, 1}, 10});   // group (0, 0, 0)
  reach.add({CellIndex{4, 0, 1}, 11});   // group (1, 0, 0)
  reach.add({CellIndex{10, 0, 1}, 12});  // group (3, 0, 0): two groups from group (1, 0, 0)
  const std::array<double, 3> unit{1, 1, 1};
  EXPECT_EQ(reach.references(CellIndex{2, 0, 1}, unit), (std::vector<uint32_t>{10, 11}));
  EXPECT_EQ(reach.references(CellIndex{5, 0, 1}, unit), (std::vector<uint32_t>{11, 10}));
  // Cell 8 is nearer to 12 than to 10, but group (0, 0, 0) is out of its reach.
  EXPECT_EQ(reach.references(CellIndex{8, 0, 1}, unit), (std::vector<uint32_t>{12, 11}));
  EXPECT_TRUE(reach.references(CellIndex{20, 0, 1}, unit).empty());
}

TEST(SpatialPlacement, RejectsBadArguments) {
  const PlacementSettings defaults;
  auto expect_invalid = [](const Result<std::vector<CellPlacement>>& r, const char* needle) {
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.status().code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(r.status().message().find(needle), std::string::npos) << r.status().message();
  };
  expect_invalid(place_cubes({{3, 0, 0}}, {3, 1, 3}, defaults), "(3, 0, 0)");
  expect_invalid(place_cubes({{-1, 0, 0}}, {3, 1, 3}, defaults), "outside");
  expect_invalid(place_cubes({{1, 0, 1}, {1, 0, 1}}, {3, 1, 3}, defaults), "twice");
  expect_invalid(place_cubes({}, {0, 1, 3}, defaults), "dims");
  PlacementSettings zero;
  zero.i_spacing = {3, 0, 3};
  expect_invalid(place_cubes({{0, 0, 0}}, {3, 1, 3}, zero), "i_spacing");
  expect_invalid(place_cubes({{0, 0, 0}}, {3, 1, 3}, defaults, {1.0, -1.0, 1.0}), "grid spacing");
  expect_invalid(place_cubes({{0, 0, 0}}, {3, 1, 3}, defaults, {1.0, NAN, 1.0}), "grid spacing");
}

}  // namespace
}  // namespace svc
