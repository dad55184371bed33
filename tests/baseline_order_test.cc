// SPDX-License-Identifier: BSD-2-Clause
// Cell orders of the baseline: row-major layout and GOP starts, Hilbert coverage and
// locality.
#include <gtest/gtest.h>

#include <cstdlib>
#include <set>
#include <tuple>

#include "baseline/baseline.h"

namespace svc::baseline {
namespace {

std::vector<CellIndex> full_grid(std::array<int, 3> dims) {
  std::vector<CellIndex> cells;
  // Deliberately not in row-major order, so the sort is exercised.
  for (int x = dims[0] - 1; x >= 0; --x)
    for (int z = 0; z < dims[2]; ++z)
      for (int y = dims[1] - 1; y >= 0; --y) cells.push_back({x, y, z});
  return cells;
}

TEST(BaselineOrderTest, RowMajorIsXFastestThenZThenLayers) {
  const std::array<int, 3> dims{3, 2, 2};
  auto sequence = order_cells(full_grid(dims), dims, CellOrder::kRowMajor);
  ASSERT_TRUE(sequence.ok()) << sequence.status().to_string();
  ASSERT_EQ(sequence->cells.size(), 12u);
  int k = 0;
  for (int y = 0; y < 2; ++y)
    for (int z = 0; z < 2; ++z)
      for (int x = 0; x < 3; ++x, ++k) {
        EXPECT_EQ(sequence->cells[k], (CellIndex{x, y, z})) << "frame " << k;
        EXPECT_EQ(sequence->gop_start[k], x == 0 ? 1 : 0) << "frame " << k;
        EXPECT_EQ(sequence->frame_of({x, y, z}), k);
      }
  EXPECT_EQ(sequence->frame_of({5, 0, 0}), -1);
}

TEST(BaselineOrderTest, RowMajorWithHolesStartsGopAtFirstPresentCellOfEachRow) {
  const std::array<int, 3> dims{4, 1, 3};
  // Row z=0 lacks x=0, row z=1 is empty, row z=2 has x=1 and x=3.
  std::vector<CellIndex> cells = {{3, 0, 2}, {1, 0, 0}, {2, 0, 0}, {1, 0, 2}, {3, 0, 0}};
  auto sequence = order_cells(cells, dims, CellOrder::kRowMajor);
  ASSERT_TRUE(sequence.ok()) << sequence.status().to_string();
  const std::vector<CellIndex> expected = {{1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {1, 0, 2}, {3, 0, 2}};
  EXPECT_EQ(sequence->cells, expected);
  EXPECT_EQ(sequence->gop_start, (std::vector<uint8_t>{1, 0, 0, 1, 0}));
}

TEST(BaselineOrderTest, HilbertDistanceOfTwoByTwoIsTheUShape) {
  EXPECT_EQ(hilbert_distance(2, 0, 0), 0u);
  EXPECT_EQ(hilbert_distance(2, 0, 1), 1u);
  EXPECT_EQ(hilbert_distance(2, 1, 1), 2u);
  EXPECT_EQ(hilbert_distance(2, 1, 0), 3u);
}

TEST(BaselineOrderTest, HilbertCoversPowerOfTwoGridOnceWithNeighbourSteps) {
  for (int side : {2, 4, 8, 16}) {
    const std::array<int, 3> dims{side, 2, side};
    auto sequence = order_cells(full_grid(dims), dims, CellOrder::kHilbert, 5);
    ASSERT_TRUE(sequence.ok()) << sequence.status().to_string();
    ASSERT_EQ(sequence->cells.size(), static_cast<size_t>(side * side * 2));
    std::set<std::tuple<int, int, int>> seen;
    for (const CellIndex& c : sequence->cells) seen.insert({c.x, c.y, c.z});
    EXPECT_EQ(seen.size(), sequence->cells.size()) << "side " << side;
    const size_t layer_size = static_cast<size_t>(side) * side;
    for (size_t k = 0; k < sequence->cells.size(); ++k) {
      const CellIndex& c = sequence->cells[k];
      EXPECT_EQ(c.y, static_cast<int>(k / layer_size)) << "layers are concatenated";
      const size_t in_layer = k % layer_size;
      EXPECT_EQ(sequence->gop_start[k], in_layer % 5 == 0 ? 1 : 0) << "frame " << k;
      if (in_layer == 0) continue;
      const CellIndex& p = sequence->cells[k - 1];
      EXPECT_EQ(std::abs(c.x - p.x) + std::abs(c.z - p.z), 1)
          << "side " << side << ", frame " << k << " is not a grid neighbour of frame " << k - 1;
    }
  }
}

TEST(BaselineOrderTest, HilbertOnSparseNonPowerOfTwoGridKeepsEveryCellOnce) {
  const std::array<int, 3> dims{5, 1, 3};
  std::vector<CellIndex> cells;
  for (const CellIndex& c : full_grid(dims)) {
    if ((c.x + 2 * c.z) % 4 != 1) cells.push_back(c);  // holes
  }
  auto sequence = order_cells(cells, dims, CellOrder::kHilbert, 6);
  ASSERT_TRUE(sequence.ok()) << sequence.status().to_string();
  ASSERT_EQ(sequence->cells.size(), cells.size());
  // Sorted by distance on the 8x8 curve.
  for (size_t k = 1; k < sequence->cells.size(); ++k) {
    const CellIndex& a = sequence->cells[k - 1];
    const CellIndex& b = sequence->cells[k];
    EXPECT_LT(hilbert_distance(8, a.x, a.z), hilbert_distance(8, b.x, b.z));
  }
}

TEST(BaselineOrderTest, RejectsDuplicatesCellsOutsideTheGridAndBadSettings) {
  const std::array<int, 3> dims{2, 1, 2};
  std::vector<CellIndex> twice = {{0, 0, 0}, {1, 0, 1}, {0, 0, 0}};
  auto duplicate = order_cells(twice, dims, CellOrder::kRowMajor);
  ASSERT_FALSE(duplicate.ok());
  EXPECT_EQ(duplicate.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(duplicate.status().message().find("(0,0,0)"), std::string::npos);

  std::vector<CellIndex> outside = {{2, 0, 0}};
  EXPECT_EQ(order_cells(outside, dims, CellOrder::kHilbert).status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(order_cells({}, {0, 1, 1}, CellOrder::kRowMajor).status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(order_cells({}, dims, CellOrder::kHilbert, 0).status().code(), ErrorCode::kInvalidArgument);

  CellOrder parsed = CellOrder::kRowMajor;
  EXPECT_TRUE(parse_cell_order(cell_order_name(CellOrder::kHilbert), &parsed));
  EXPECT_EQ(parsed, CellOrder::kHilbert);
  EXPECT_FALSE(parse_cell_order("zigzag", &parsed));
}

}  // namespace
}  // namespace svc::baseline
