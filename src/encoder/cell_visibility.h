// SPDX-License-Identifier: BSD-2-Clause
// What the cubes of a database see of each other, from its depth: the input of I-cube
// placement and reference choice by visibility (spatial/placement.h). Shared by a full
// encode, `svc add` and the placement bench.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "database/database.h"
#include "spatial/placement.h"
#include "spatial/visibility.h"
#include "svc/status.h"

namespace svc {

// Measures visibility pairs over placement cells where cell c's faces are
// manifest.cells[*sources[c]] (nullopt: the database does not hold the cell; it gets no
// samples and no pairs). A cell's sampled depth (spatial/visibility.h, CubeSamples) is
// loaded when a pair needs it and kept in a least-recently-used cache of at most
// `cache_bytes` between batches of cells, so the memory held does not grow with the
// database: the cache, one batch's cubes, and the table's counts (a few bytes a pair).
// Cells are measured in (y, z, x) order, so the cubes a batch needs are mostly those
// the batches before it loaded. The table never depends on the budget, the order or the
// thread count. Not thread-safe: one caller at a time (it runs `threads` itself).
class VisibilityMeter {
 public:
  VisibilityMeter(const DatabaseManifest& manifest, std::vector<std::optional<size_t>> sources, int threads,
                  uint64_t cache_bytes);
  // A table with every cell's sample count (from the face size) and no pairs.
  VisibilityTable empty_table() const;
  // For every cell that is the first of a pair of `pairs` whose cells are both held,
  // measures what each of those pairs' references sees of it and sets them in `table`
  // (replacing what it held for the cell). Errors: those of load_face, naming the cell,
  // face and file; kBadInput when a face's depth does not have the manifest's face size.
  Status measure(const std::vector<std::pair<uint32_t, uint32_t>>& pairs, VisibilityTable* table);
  // Most bytes of sampled cubes held at once so far, cache and batch together.
  uint64_t peak_bytes() const { return peak_bytes_; }

 private:
  struct CachedCube {
    std::shared_ptr<const CubeSamples> samples;
    uint64_t bytes = 0;
    uint64_t last_batch = 0;
  };
  Status load_missing(const std::vector<uint32_t>& cells);
  void evict_to_budget();

  const DatabaseManifest& manifest_;
  std::vector<std::optional<size_t>> sources_;
  int threads_;
  uint64_t cache_bytes_;
  std::unordered_map<uint32_t, CachedCube> cache_;
  uint64_t held_bytes_ = 0, peak_bytes_ = 0, batch_ = 0;
};

// One meter's table of `pairs`, with the reference caches' budget (reference_cache_bytes).
Result<VisibilityTable> measure_visibility(const DatabaseManifest& manifest,
                                           const std::vector<std::optional<size_t>>& sources,
                                           const std::vector<std::pair<uint32_t, uint32_t>>& pairs, int threads);

}  // namespace svc
