// SPDX-License-Identifier: BSD-2-Clause
// A simulated walkthrough over svc::Reader: a viewer moves along a path at a fixed speed
// and, each time it enters a cell, asks for that cell's six faces. Measures how long each
// of those requests takes, with the reader's background prefetch on or off.
//
// Uses only the public API (include/svc), as a runtime embedding the library would.
// Threading: replay() is reentrant; each call opens its own reader.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "svc/reader.h"
#include "svc/status.h"

namespace svc::walkthrough {

using Position = std::array<double, 3>;

// The length speeds are counted in: the smallest grid spacing among the axes the grid
// extends along (the smallest spacing of all when it extends along none).
double cell_length(const FileInfo& info);

// The built-in path: every present cell's centre once, layer by layer (y ascending),
// rows of z in a serpentine (x ascending on even rows, descending on odd rows; odd
// layers walk their rows backwards), so consecutive waypoints are neighbouring cells
// wherever the grid has no holes.
std::vector<Position> builtin_path(const Reader& reader);

// A path file: one waypoint "x y z" (world coordinates, whitespace separated) per line;
// blank lines and everything after '#' are ignored. kBadInput naming the line for
// anything else; kNotFound when the file cannot be opened; at least one waypoint.
Result<std::vector<Position>> read_path_file(const std::filesystem::path& path);

struct ReplayOptions {
  // Viewer speed in cells per second; a cell is the smallest grid spacing among the axes
  // the grid extends along.
  double cells_per_second = 1.0;
  bool prefetch = true;
  // Stop after this many cell entries; 0 = the whole path.
  int max_steps = 0;
  // false: when prefetch has nothing left to do before the viewer reaches the next
  // cell, skip the idle rest of the interval (the outcome is the same as waiting it
  // out, since nothing runs meanwhile). true: sleep in real time.
  bool realtime = false;
  // With prefetch, announce the start position and wait for its neighbourhood before
  // the clock starts, as a runtime's loading screen would.
  bool warm_start = true;
  // Reader settings; prefetch_threads is forced to 0 when prefetch is false.
  ReaderSettings reader = default_reader_settings();
};

struct ReplayResult {
  bool prefetch = false;
  int steps = 0;                                           // cell entries timed
  double simulated_seconds = 0;                            // the viewer's travel time over those steps
  double wall_seconds = 0;                                 // what the replay took (less when idle time was skipped)
  std::vector<double> latency_ms;                          // per step: time to obtain the six faces as RGB
  double p50_ms = 0, p99_ms = 0, max_ms = 0, mean_ms = 0;  // nearest-rank percentiles
  int steps_waiting = 0;                                   // steps where a face had to be decoded (or awaited)
  double face_hit_rate = 0;                                // of the steps' face requests
  double coefficient_hit_rate = 0;  // of semi-decoded I-face lookups made for requests; -1: none
  ReaderStats stats;                // the reader's counters at the end
  uint64_t memory_held = 0;         // the three caches at the end
  uint64_t memory_peak = 0;         // sum of the three caches' peaks
};

Result<ReplayResult> replay(const std::filesystem::path& svc_file, const std::vector<Position>& path,
                            const ReplayOptions& options);

}  // namespace svc::walkthrough
