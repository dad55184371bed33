// SPDX-License-Identifier: BSD-2-Clause
// Visibility on the generated house (rooms behind walls): what the measure sees, which
// references it picks, and the encoder's visibility layout.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "common/parallel.h"
#include "database/database.h"
#include "encoder/cell_visibility.h"
#include "samples/scene/scene.h"
#include "spatial/placement.h"
#include "spatial/visibility.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace svc {
namespace {

// Bits set in `bits`.
size_t count_seen(const std::vector<uint64_t>& bits) { return count_seen_by_either(bits, bits); }

namespace fs = std::filesystem;

samples::SceneOptions house_options() {
  samples::SceneOptions options;
  options.kind = samples::SceneKind::kHouse;
  options.grid = {9, 1, 9};
  options.face_size = 64;
  return options;
}

// A smaller house written as a database.
Status write_house(const fs::path& out, const std::array<int, 3>& grid, int face_size) {
  samples::SceneOptions options = house_options();
  options.grid = grid;
  options.face_size = face_size;
  return samples::generate_scene(options, out);
}

// Every cell of the house: index, room and sampled depth.
struct House {
  std::vector<CellIndex> cells;
  std::vector<int> rooms;
  std::vector<CubeSamples> cubes;
};

const House& house() {
  static const House built = [] {
    const samples::SceneOptions options = house_options();
    House h;
    auto infos = samples::describe_scene_cells(options);
    EXPECT_TRUE(infos.ok());
    for (const auto& info : *infos) {
      h.cells.push_back(info.index);
      h.rooms.push_back(info.room);
    }
    h.cubes.resize(h.cells.size());
    const Frustum frustum =
        symmetric_frustum(samples::kSceneFovYDegrees, 1.0, samples::kSceneNear, samples::kSceneFar);
    const Status status = parallel_for(h.cells.size(), 2, [&](size_t c) -> Status {
      for (Face face : kAllFaces) {
        SVC_ASSIGN_OR_RETURN(samples::SceneFace rendered, samples::render_scene_face(options, h.cells[c], face));
        Camera camera{rendered.world_to_camera, frustum};
        if (!add_face_samples(&h.cubes[c], face, camera, options.face_size, options.face_size, rendered.depth)) {
          return Status(ErrorCode::kInternal, "sampling failed");
        }
      }
      return Status::Ok();
    });
    EXPECT_TRUE(status.ok()) << status.to_string();
    return h;
  }();
  return built;
}

VisibilityTable house_table(const House& h) {
  VisibilityTable table(h.cells.size());
  for (uint32_t c = 0; c < h.cells.size(); ++c) table.set_samples(c, sample_count(h.cubes[c]));
  auto pairs = reach_pairs(h.cells, {3, 1, 3});
  EXPECT_TRUE(pairs.ok());
  std::map<uint32_t, std::vector<std::pair<uint32_t, std::vector<uint64_t>>>> by_cell;
  for (const auto& [cell, reference] : *pairs)
    by_cell[cell].emplace_back(reference, seen_by(h.cubes[cell], h.cubes[reference]));
  for (const auto& [cell, seen] : by_cell) table.set_seen(cell, seen);
  return table;
}

TEST(Visibility, ACubeSeesAllOfItself) {
  const House& h = house();
  for (size_t c : {size_t{0}, size_t{40}, size_t{80}}) {
    const size_t samples = sample_count(h.cubes[c]);
    ASSERT_EQ(samples, 6u * 16 * 16);
    EXPECT_EQ(count_seen(seen_by(h.cubes[c], h.cubes[c])), samples) << cell_label(h.cells[c]);
  }
}

TEST(Visibility, NeighboursInTheSameRoomSeeMoreThanNeighboursBehindAWall) {
  const House& h = house();
  double same_room = 0, other_room = 0;
  size_t same_count = 0, other_count = 0;
  for (size_t c = 0; c < h.cells.size(); ++c) {
    for (size_t n = 0; n < h.cells.size(); ++n) {
      if (std::abs(h.cells[n].x - h.cells[c].x) + std::abs(h.cells[n].z - h.cells[c].z) != 1) continue;
      const double share = static_cast<double>(count_seen(seen_by(h.cubes[c], h.cubes[n]))) /
                           static_cast<double>(sample_count(h.cubes[c]));
      (h.rooms[n] == h.rooms[c] ? same_room : other_room) += share;
      ++(h.rooms[n] == h.rooms[c] ? same_count : other_count);
    }
  }
  ASSERT_GT(same_count, 0u);
  ASSERT_GT(other_count, 0u);
  // Doorways let a neighbour in the next room see some of a cell; walls hide the rest.
  EXPECT_GT(same_room / same_count, 0.8);
  EXPECT_LT(other_room / other_count, same_room / same_count - 0.2);
}

TEST(Visibility, CellBehindAWallGetsAReferenceThatSeesIt) {
  const House& h = house();
  const VisibilityTable table = house_table(h);
  PlacementSettings by_distance;
  PlacementSettings by_sight;
  by_sight.visibility_references = true;
  auto nearest = place_cubes(h.cells, {9, 1, 9}, by_distance, {0.5, 1, 0.5}, &table);
  auto visible = place_cubes(h.cells, {9, 1, 9}, by_sight, {0.5, 1, 0.5}, &table);
  ASSERT_TRUE(nearest.ok() && visible.ok());
  auto seen_by_refs = [&](uint32_t c, const std::vector<uint32_t>& refs) {
    return table.seen_by_either(c, refs[0], refs.back());
  };
  auto behind_walls = [&](uint32_t c, const std::vector<uint32_t>& refs) {
    return std::count_if(refs.begin(), refs.end(), [&](uint32_t r) { return h.rooms[r] != h.rooms[c]; });
  };
  size_t walled = 0, improved = 0;
  long behind_before = 0, behind_after = 0;
  for (uint32_t c = 0; c < h.cells.size(); ++c) {
    const auto& near_refs = (*nearest)[c].references;
    const auto& sight_refs = (*visible)[c].references;
    EXPECT_EQ((*nearest)[c].intra, (*visible)[c].intra);
    if ((*nearest)[c].intra) continue;
    ASSERT_EQ(sight_refs.size(), near_refs.size());
    // A pair other than the nearest is chosen only when it sees more.
    if (sight_refs != near_refs) {
      EXPECT_GT(seen_by_refs(c, sight_refs), seen_by_refs(c, near_refs)) << cell_label(h.cells[c]);
      ++improved;
    }
    behind_before += behind_walls(c, near_refs);
    behind_after += behind_walls(c, sight_refs);
    walled += behind_walls(c, near_refs) > 0 ? 1 : 0;
  }
  EXPECT_GT(walled, 10u);  // cells with one of their nearest two I-cubes in another room
  EXPECT_GT(improved, 5u);
  EXPECT_LT(behind_after, behind_before) << "references behind walls";
}

// The estimated cost (placement.h, LayoutCosts) of a placement over the house.
double estimated_cost(const House& h, const VisibilityTable& table, const std::vector<CellPlacement>& placement) {
  const LayoutCosts costs;
  double total = 0;
  for (uint32_t c = 0; c < h.cells.size(); ++c) {
    const auto& refs = placement[c].references;
    if (placement[c].intra) {
      total += 1.0;
      continue;
    }
    const size_t seen = table.seen_by_either(c, refs[0], refs.back());
    const double share = static_cast<double>(seen) / static_cast<double>(table.samples(c));
    total += costs.seen_b_face * share + costs.unseen_b_face * (1.0 - share);
  }
  return total;
}

TEST(Visibility, LayoutKeepsTheLatticeAndNeverRaisesTheEstimatedCost) {
  const House& h = house();
  const VisibilityTable table = house_table(h);
  PlacementSettings settings;
  settings.layout = Layout::kVisibility;
  settings.visibility_references = true;
  auto placement = place_cubes(h.cells, {9, 1, 9}, settings, {0.5, 1, 0.5}, &table);
  PlacementSettings sight;
  sight.visibility_references = true;
  auto regular = place_cubes(h.cells, {9, 1, 9}, sight, {0.5, 1, 0.5}, &table);
  ASSERT_TRUE(placement.ok() && regular.ok());
  for (size_t c = 0; c < h.cells.size(); ++c) {
    if ((*regular)[c].intra) EXPECT_TRUE((*placement)[c].intra) << "the lattice's I-cubes stay";
    EXPECT_LE((*placement)[c].references.size(), 2u);
    for (uint32_t r : (*placement)[c].references) EXPECT_TRUE((*placement)[r].intra);
  }
  EXPECT_LE(estimated_cost(h, table, *placement), estimated_cost(h, table, *regular) + 1e-9);
}

TEST(Visibility, EncodeIsTheSameForAnyThreadCountAndStaysWithinTwoReferences) {
  testing::TempDir dir;
  ASSERT_TRUE(write_house(dir.path() / "db", {6, 1, 6}, 32).ok());
  EncoderSettings settings;
  settings.threads = 1;
  ASSERT_TRUE(encode_database(dir.path() / "db", dir.path() / "one.svc", settings).ok());
  settings.threads = 3;
  auto summary = encode_database(dir.path() / "db", dir.path() / "three.svc", settings);
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  EXPECT_EQ(testing::read_file_bytes(dir.path() / "one.svc"), testing::read_file_bytes(dir.path() / "three.svc"));
  settings.layout = CubeLayout::kRegular;
  auto regular = encode_database(dir.path() / "db", dir.path() / "regular.svc", settings);
  ASSERT_TRUE(regular.ok());
  EXPECT_GE(summary->intra.faces, regular->intra.faces);

  auto reader = Reader::open(dir.path() / "one.svc");
  ASSERT_TRUE(reader.ok());
  EXPECT_TRUE((*reader)->verify().ok());
  for (const CellEntry& cell : (*reader)->cells()) {
    for (Face face : kAllFaces) {
      const FaceEntry& entry = cell.faces[static_cast<int>(face)];
      // Its own face of at most two reference cubes, and with cube references the faces
      // of those cubes adjacent to it: all I-faces.
      std::set<uint32_t> reference_cells;
      for (const auto& [ref_cell, ref_face] : entry.references) {
        reference_cells.insert(ref_cell);
        const CellEntry& ref = (*reader)->cells().at(ref_cell);
        EXPECT_EQ(ref.faces[static_cast<int>(ref_face)].type, FaceType::kIntra) << "references are I-faces";
      }
      ASSERT_LE(reference_cells.size(), 2u);
    }
  }
}

TEST(Visibility, MeterGivesTheSameTableUnderAnyBudgetAndHoldsWithinIt) {
  testing::TempDir dir;
  ASSERT_TRUE(write_house(dir.path() / "db", {12, 1, 12}, 16).ok());
  auto manifest = load_manifest(dir.path() / "db");
  ASSERT_TRUE(manifest.ok()) << manifest.status().to_string();
  std::vector<CellIndex> cells;
  std::vector<std::optional<size_t>> sources;
  for (size_t c = 0; c < manifest->cells.size(); ++c) {
    cells.push_back(manifest->cells[c].index);
    sources.emplace_back(c);
  }
  auto lattice = place_cubes(cells, {12, 1, 12}, PlacementSettings{});
  auto all_pairs = reach_pairs(cells, {3, 1, 3});
  ASSERT_TRUE(lattice.ok() && all_pairs.ok());
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (const auto& pair : *all_pairs) {
    if ((*lattice)[pair.second].intra) pairs.push_back(pair);
  }
  // Every cube at once, against a budget of one byte: only the batch's cubes are held.
  VisibilityMeter roomy(*manifest, sources, 2, uint64_t{1} << 30), tight(*manifest, sources, 1, 1);
  VisibilityTable wide = roomy.empty_table(), narrow = tight.empty_table();
  ASSERT_TRUE(roomy.measure(pairs, &wide).ok());
  ASSERT_TRUE(tight.measure(pairs, &narrow).ok());
  size_t partly_seen = 0;
  for (const auto& [cell, reference] : pairs) {
    ASSERT_TRUE(narrow.has(cell, reference));
    EXPECT_EQ(wide.samples(cell), 6u * 4 * 4);
    for (const auto& [other_cell, other] : pairs) {
      if (other_cell != cell) continue;
      EXPECT_EQ(narrow.seen_by_either(cell, reference, other), wide.seen_by_either(cell, reference, other));
    }
    const size_t alone = narrow.seen_by_either(cell, reference, reference);
    partly_seen += alone > 0 && alone < narrow.samples(cell);
  }
  EXPECT_GT(partly_seen, 10u) << "walls hide part of some cells";
  EXPECT_LT(tight.peak_bytes() * 3, roomy.peak_bytes());

  // A pair not measured is not held and counts nothing.
  const auto& [cell, reference] = pairs[pairs.size() / 2];
  ASSERT_TRUE(wide.has(cell, reference));
  EXPECT_FALSE(wide.has(cell, cell));
  EXPECT_EQ(wide.seen_by_either(cell, cell, reference), 0u);
}

}  // namespace
}  // namespace svc
