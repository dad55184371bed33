// SPDX-License-Identifier: BSD-2-Clause
// I-cube / B-cube placement over the cell grid and reference selection
// (dissertation section 4.2.3.1, Figure 4.3).
//
// Rules (they are part of the file format's meaning: an encoder and any tool that
// re-derives the dependency graph must agree on them):
//
// Groups. The grid is tiled by groups of i_spacing[0] x i_spacing[1] x i_spacing[2]
//   cells: cell (x, y, z) belongs to group (x / sx, y / sy, z / sz). Groups at the far
//   edge of a grid whose size is not a multiple of the spacing are partial.
// Nominal I-cube. The nominal I-cube of a group is the cell at index g*s + s/2 on each
//   axis (integer division): the centre for odd s (s=3: 1, 4, 7, ...), the upper of the
//   two middle cells for even s (s=2: 1, 3, 5, ...; s=4: 2, 6, ...), and every cell for
//   s=1 (intra-only along that axis).
// Relocation. When the nominal cell is absent (a hole in a sparse grid, or outside the
//   grid for a partial edge group), the group's I-cube is its present cell nearest to the
//   nominal position by cell-centre distance; ties go to the smallest (y, z, x) index.
//   A group with no present cell has no I-cube. So every group that holds a cell holds
//   exactly one I-cube.
// Reach. A B-cube may reference the I-cubes of its own group and of the groups adjacent
//   to it (group indices differing by at most 1 on every axis: up to 27 groups). Its own
//   group always has an I-cube, so every B-cube has at least one reference.
// References. Of the I-cubes in reach, the nearest two by Euclidean distance between
//   cell centres (index difference times grid spacing per axis); ties go to the smallest
//   (y, z, x) index. Distances equal within a relative 1e-9 count as ties. A B-cube with
//   only one I-cube in reach gets one reference. References are always I-cubes, never
//   B-cubes, so any face decodes from at most two reference faces.
//
// B:I ratio of full groups = (sx*sy*sz - 1) : 1.
//   {1,1,1}            intra-only (0:1)
//   {3,1,3} (default)  8:1, the VWALK layout: the centre of each 3x3 group of a layer
//   {3,1,2} / {2,1,3}  5:1
//   {3,2,3} / {6,1,3}  17:1   ({6,1,3} on a single-layer grid)
//   {3,3,3} / {9,1,3}  26:1   ({9,1,3} on a single-layer grid)
// Along an axis with fewer cells than its spacing the groups are partial, so a
// single-layer grid with sy > 1 behaves as sy = 1. Partial edge groups and sparse grids
// make the measured ratio lower than the nominal one.
//
// Threading: pure functions of their arguments; safe to call concurrently.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "svc/status.h"
#include "svc/types.h"

namespace svc {

// Largest i_spacing accepted on any axis.
inline constexpr int32_t kMaxIntraSpacing = 1024;

// Where I-cubes go. kRegular: the lattice above, one per group. kVisibility: the lattice,
// then further I-cubes added one at a time where the references in reach see too little
// of the cells around them, each the addition that lowers the estimated cost most
// (LayoutCosts), until no addition lowers it (see place_cubes).
enum class Layout : uint8_t { kRegular = 0, kVisibility = 1 };

// Estimated bytes of a face, in units of an I-face's, that the visibility layout weighs.
// A B-face costs seen_b_face when its references together see all of it, unseen_b_face
// when they see none of it, and in between in proportion to the share they see. Measured
// on the photographic hall and house (docs/encoder.md 8).
struct LayoutCosts {
  double seen_b_face = 0.3;
  double unseen_b_face = 0.5;
};

// I-cube spacing per axis (x, y, z). {3,1,3} puts an I-cube at the centre of each 3x3
// group of cells in a layer (VWALK). A spacing of 1 on every axis is intra-only.
struct PlacementSettings {
  std::array<int32_t, 3> i_spacing{3, 1, 3};
  Layout layout = Layout::kRegular;
  // References: the pair in reach that together sees most of the cell (ties by the
  // distance order of the References rule) instead of the nearest two.
  bool visibility_references = false;
  LayoutCosts costs;
};

struct CellPlacement {
  bool intra = true;
  // Ordinals (into the `cells` argument) of the reference I-cubes, nearest first;
  // empty for an I-cube, one or two entries for a B-cube.
  std::vector<uint32_t> references;
};

// `cells` are the present cells of the grid (any order, no duplicates); `dims` the grid
// size; `grid_spacing` the distance between neighbouring cell centres per axis (the
// manifest's grid.spacing), used for every distance above. Returns one entry per cell,
// in the same order. The result depends only on the set of cells, not on their order
// (beyond the ordinals themselves). Errors (kInvalidArgument): dims or spacings not
// positive, a spacing above kMaxIntraSpacing, a grid spacing not finite and positive, a
// cell outside dims, or a duplicate cell; the message names the offending value.
Result<std::vector<CellPlacement>> place_cubes(const std::vector<CellIndex>& cells,
                                               const std::array<int32_t, 3>& dims,
                                               const PlacementSettings& settings,
                                               const std::array<double, 3>& grid_spacing);

// What reference cubes see of cells, by cell ordinal (into place_cubes' `cells`): per
// cell its number of sample points and, for the references measured for it, how many
// of its samples each sees and each two see together (spatial/visibility.h, seen_by).
// Counts only, no bitsets: a few bytes a pair, so a table of a whole database stays
// small whatever the face size. Filled by the caller for the pairs reach_pairs lists.
class VisibilityTable {
 public:
  explicit VisibilityTable(size_t cells) : samples_(cells, 0), seen_(cells) {}
  void set_samples(uint32_t cell, size_t count) { samples_.at(cell) = count; }
  // What each reference sees of `cell`, as bitsets of the cell's samples (one length).
  // Replaces what the table held for the cell, so a caller adding references to a cell
  // passes all of them again.
  void set_seen(uint32_t cell, const std::vector<std::pair<uint32_t, std::vector<uint64_t>>>& seen);
  size_t cells() const { return samples_.size(); }
  size_t samples(uint32_t cell) const { return cell < samples_.size() ? samples_[cell] : 0; }
  // Whether the table holds what `reference` sees of `cell`.
  bool has(uint32_t cell, uint32_t reference) const;
  // Samples of `cell` that `first` or `second` sees (the same reference twice: what it
  // alone sees). Both must be held (has); 0 otherwise.
  size_t seen_by_either(uint32_t cell, uint32_t first, uint32_t second) const;

 private:
  // The references of a cell, sorted, and the counts of every pair (i <= j) of them,
  // row by row of the upper triangle (i == j: what reference i sees).
  struct CellSeen {
    std::vector<uint32_t> references;
    std::vector<uint32_t> counts;
  };
  std::vector<size_t> samples_;
  std::vector<CellSeen> seen_;
};

// The (cell, reference) ordinal pairs place_cubes may ask a VisibilityTable for: every
// two distinct cells where the second lies in the first's reach (own or adjacent
// group). Sorted. Same errors as place_cubes for the cells and spacing.
Result<std::vector<std::pair<uint32_t, uint32_t>>> reach_pairs(const std::vector<CellIndex>& cells,
                                                               const std::array<int32_t, 3>& i_spacing);

// Placement with the layout and reference rule of `settings`. `visibility` must hold
// the pairs of reach_pairs whose reference is an I-cube when settings.layout is
// kVisibility or settings.visibility_references is set (kInvalidArgument otherwise); it
// may be null for the regular layout with the nearest references. The visibility layout keeps the
// lattice's I-cubes and adds others greedily among the B-cubes all of whose pairs the
// table holds (see layout_candidates): the added cube is the B-cube whose
// change lowers sum over cells of (1 for an I-cube; seen_b_face * s + unseen_b_face *
// (1 - s) for a B-cube whose best pair in reach sees the share s of its samples) most,
// ties to the smallest (y, z, x) index, until no change lowers it. A pure function of
// the cells, settings and table: every caller computes the same placement.
Result<std::vector<CellPlacement>> place_cubes(const std::vector<CellIndex>& cells,
                                               const std::array<int32_t, 3>& dims,
                                               const PlacementSettings& settings,
                                               const std::array<double, 3>& grid_spacing,
                                               const VisibilityTable* visibility);

// The B-cubes of the lattice that the visibility layout could make I-cubes: those whose
// change would lower the estimated cost even if every B-cube in their reach came to be
// seen whole. Needs in `visibility` only the pairs (c, k) of reach_pairs whose k is an
// I-cube of the lattice. Once the table also holds every pair (c, k) for the cells k
// listed here, place_cubes gives the same placement as with every pair of reach_pairs
// (it considers as additions only cells all of whose pairs the table holds), so a caller
// need not measure the rest. Sorted; same errors as place_cubes.
Result<std::vector<uint32_t>> layout_candidates(const std::vector<CellIndex>& cells,
                                                const std::array<int32_t, 3>& dims,
                                                const PlacementSettings& settings,
                                                const std::array<double, 3>& grid_spacing,
                                                const VisibilityTable& visibility);

// As above with unit grid spacing (distances in cell-index units).
Result<std::vector<CellPlacement>> place_cubes(const std::vector<CellIndex>& cells,
                                               const std::array<int32_t, 3>& dims,
                                               const PlacementSettings& settings);

// An I-cube that may serve as a reference: its grid index and the caller's id for it.
struct ReferenceCandidate {
  CellIndex index;
  uint32_t id = 0;
};

// The Reach and References rules over a set of I-cubes: place_cubes and `svc add`
// (whose existing I-cubes may differ per face direction) both choose references with it.
class ReachIndex {
 public:
  explicit ReachIndex(const std::array<int32_t, 3>& i_spacing) : spacing_(i_spacing) {}
  // Makes `candidate` a possible reference of the cells in reach of it.
  void add(const ReferenceCandidate& candidate);
  // The ids of the (at most) two I-cubes in reach of `cell` nearest to it, nearest
  // first; empty when none is in reach.
  std::vector<uint32_t> references(const CellIndex& cell, const std::array<double, 3>& grid_spacing) const;
  // Every candidate in reach of `cell`, in group order.
  std::vector<ReferenceCandidate> in_reach(const CellIndex& cell) const;

 private:
  std::array<int32_t, 3> spacing_;
  std::map<std::array<int32_t, 3>, std::vector<ReferenceCandidate>> by_group_;
};

// The ids of the (at most) two candidates nearest to `cell` by the References rule
// above: distance between cell centres scaled by `grid_spacing`, ties within a relative
// 1e-9 broken by the smallest (y, z, x) index. Nearest first. place_cubes and `svc add`
// both choose references with it.
std::vector<uint32_t> nearest_references(const CellIndex& cell, const std::vector<ReferenceCandidate>& candidates,
                                         const std::array<double, 3>& grid_spacing);

// What candidates see of one cell: the samples candidate `first` or candidate `second`
// sees (the same id twice: what it alone sees).
using SeenByEither = std::function<size_t(uint32_t first, uint32_t second)>;

// The (at most) two candidates that together see most of a cell: the pair (or, with one
// candidate, the single one) that sees most of it by `seen`. Of pairs that see as much,
// the first in the lexicographic order of their members' ranks by the References rule
// (distance, then (y, z, x) index) wins, so where every pair sees all it is the nearest
// two. Nearest first.
std::vector<uint32_t> visible_references(const CellIndex& cell, const std::vector<ReferenceCandidate>& candidates,
                                         const std::array<double, 3>& grid_spacing, const SeenByEither& seen);

}  // namespace svc
