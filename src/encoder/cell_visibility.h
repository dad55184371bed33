// What the cubes of a database see of each other, from its depth: the input of I-cube
// placement and reference choice by visibility (spatial/placement.h). Shared by a full
// encode and `svc add`.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "database/database.h"
#include "spatial/placement.h"
#include "spatial/visibility.h"
#include "svc/status.h"

namespace svc {

// A table over placement cells where cell c's faces are manifest.cells[*sources[c]]
// (nullopt: the database does not hold the cell; it gets no samples and no pairs). Fills
// every pair of `pairs` whose cells both have faces: what the second sees of the first
// (spatial/visibility.h, seen_by). Loads each face's depth once, on up to `threads`
// threads; the table does not depend on the thread count. Errors: those of load_face,
// naming the cell, face and file; kBadInput when a face's depth does not have the
// manifest's face size.
// The sampled depth of a database's cells, loaded once, from which visibility pairs are
// measured in as many steps as the caller needs.
class CellVisibility {
 public:
  // Loads the cells of `sources` (as for measure_visibility), on up to `threads` threads.
  static Result<CellVisibility> load(const DatabaseManifest& manifest,
                                     const std::vector<std::optional<size_t>>& sources, int threads);
  // A table with every cell's sample count and no pairs.
  VisibilityTable empty_table() const;
  // Adds to `table` each pair of `pairs` whose cells both have samples.
  void measure(const std::vector<std::pair<uint32_t, uint32_t>>& pairs, int threads, VisibilityTable* table) const;

 private:
  std::vector<CubeSamples> cubes_;
  std::vector<uint8_t> present_;
};

Result<VisibilityTable> measure_visibility(const DatabaseManifest& manifest,
                                           const std::vector<std::optional<size_t>>& sources,
                                           const std::vector<std::pair<uint32_t, uint32_t>>& pairs, int threads);

}  // namespace svc
