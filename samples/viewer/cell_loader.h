// SPDX-License-Identifier: BSD-2-Clause
// The viewer's side of svc::Reader: which cell to show for a position, its faces (and
// depth) decoded into CellImages, the prefetcher kept on the viewer, and the figures the
// overlay shows (decode latency, cache hits and misses).
#pragma once

#include <deque>
#include <filesystem>
#include <memory>

#include <glm/vec3.hpp>

#include "svc/reader.h"
#include "viewer/cell_images.h"

namespace svc::viewer {

class CellLoader {
 public:
  // Opens the file; `depth` asks for each cell's depth as well when the file holds it.
  static Result<std::unique_ptr<CellLoader>> open(const std::filesystem::path& path, bool depth);

  const FileInfo& info() const { return reader_->info(); }
  // Whether the file holds depth.
  bool file_has_depth() const;
  // The present cell whose box holds `p`, else the present cell whose centre is nearest.
  CellIndex cell_for(const glm::dvec3& p) const;
  glm::dvec3 cell_centre(const CellIndex& cell) const;

  // Decodes the cell's six faces as RGBA (and their depth, when asked for and present)
  // and records how long that took.
  Status load(const CellIndex& cell, CellImages* out);
  // Points the reader's prefetch at the viewer.
  Status follow(const glm::dvec3& position, const glm::dvec3& velocity);

  double last_latency_ms() const { return latencies_.empty() ? 0 : latencies_.back(); }
  // Nearest-rank percentile of the latencies of the last loads (up to kLatencyWindow).
  double latency_percentile_ms(double q) const;
  int loads() const { return loads_; }
  ReaderStats stats() const { return reader_->stats(); }

  static constexpr size_t kLatencyWindow = 1000;

 private:
  explicit CellLoader(std::unique_ptr<Reader> reader, bool depth) : reader_(std::move(reader)), depth_(depth) {}
  Status load_depth(const CellIndex& cell, CellImages* out);

  std::unique_ptr<Reader> reader_;
  bool depth_ = false;
  std::deque<double> latencies_;
  int loads_ = 0;
};

}  // namespace svc::viewer
