// SPDX-License-Identifier: BSD-2-Clause
#include "walkthrough/replay.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

namespace svc::walkthrough {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// One cell entry along the path.
struct Event {
  double time = 0;  // seconds from the start of the walk
  Position position{};
  Position velocity{};
  CellIndex cell;
};

CellIndex grid_cell(const FileInfo& info, const Position& p) {
  int32_t index[3];
  for (int axis = 0; axis < 3; ++axis) {
    const double t = std::floor((p[axis] - info.grid_origin[axis]) / info.grid_spacing[axis] + 0.5);
    index[axis] = static_cast<int32_t>(std::clamp(t, -1.0, static_cast<double>(info.grid_dims[axis])));
  }
  return CellIndex{index[0], index[1], index[2]};
}

// Walks the polyline at `speed` world units per second and records each entry into a
// present cell (sampled every 1/16 of a cell).
std::vector<Event> cell_entries(const Reader& reader, const std::vector<Position>& path, double speed) {
  const FileInfo& info = reader.info();
  const double step = cell_length(info) / 16;
  std::vector<Event> events;
  std::optional<CellIndex> current;
  double travelled = 0;
  auto visit = [&](const Position& p, const Position& velocity, double distance) {
    const CellIndex cell = grid_cell(info, p);
    if (current && *current == cell) return;
    current = cell;
    if (!reader.find_cell(cell)) return;  // outside the grid or a hole: nothing to show
    events.push_back(Event{distance / speed, p, velocity, cell});
  };
  if (path.empty()) return events;
  visit(path[0], {0, 0, 0}, 0);
  for (size_t i = 1; i < path.size(); ++i) {
    const Position& a = path[i - 1];
    const Position& b = path[i];
    const double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
    const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (length == 0) continue;
    const Position velocity{dx / length * speed, dy / length * speed, dz / length * speed};
    if (events.size() == 1 && events[0].time == 0) events[0].velocity = velocity;
    const int samples = std::max(1, static_cast<int>(std::ceil(length / step)));
    for (int s = 1; s <= samples; ++s) {
      const double f = static_cast<double>(s) / samples;
      visit({a[0] + f * dx, a[1] + f * dy, a[2] + f * dz}, velocity, travelled + f * length);
    }
    travelled += length;
  }
  return events;
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t rank = static_cast<size_t>(std::ceil(q * values.size()));
  return values[std::clamp<size_t>(rank, 1, values.size()) - 1];
}

}  // namespace

double cell_length(const FileInfo& info) {
  double length = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (info.grid_dims[axis] > 1 && (length == 0 || info.grid_spacing[axis] < length)) {
      length = info.grid_spacing[axis];
    }
  }
  return length > 0 ? length : std::min({info.grid_spacing[0], info.grid_spacing[1], info.grid_spacing[2]});
}

std::vector<Position> builtin_path(const Reader& reader) {
  const FileInfo& info = reader.info();
  std::vector<Position> path;
  for (int32_t y = 0; y < info.grid_dims[1]; ++y) {
    for (int32_t row = 0; row < info.grid_dims[2]; ++row) {
      const int32_t z = (y % 2 == 0) ? row : info.grid_dims[2] - 1 - row;
      for (int32_t column = 0; column < info.grid_dims[0]; ++column) {
        const int32_t x = ((row + y) % 2 == 0) ? column : info.grid_dims[0] - 1 - column;
        const auto ordinal = reader.find_cell(CellIndex{x, y, z});
        if (!ordinal) continue;
        path.push_back({info.grid_origin[0] + x * info.grid_spacing[0],
                        info.grid_origin[1] + y * info.grid_spacing[1],
                        info.grid_origin[2] + z * info.grid_spacing[2]});
      }
    }
  }
  return path;
}

Result<std::vector<Position>> read_path_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return Status(ErrorCode::kNotFound, "cannot open path file " + path.string());
  std::vector<Position> positions;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    Position p{};
    std::string extra;
    if (!(fields >> std::ws) || fields.eof()) continue;  // blank
    if (!(fields >> p[0] >> p[1] >> p[2]) || (fields >> extra) || !std::isfinite(p[0]) || !std::isfinite(p[1]) ||
        !std::isfinite(p[2])) {
      return Status(ErrorCode::kBadInput,
                    path.string() + ":" + std::to_string(number) + ": expected three finite numbers \"x y z\"");
    }
    positions.push_back(p);
  }
  if (positions.empty()) return Status(ErrorCode::kBadInput, path.string() + ": no waypoints");
  return positions;
}

Result<ReplayResult> replay(const std::filesystem::path& svc_file, const std::vector<Position>& path,
                            const ReplayOptions& options) {
  if (!(options.cells_per_second > 0) || !std::isfinite(options.cells_per_second)) {
    return Status(ErrorCode::kInvalidArgument, "speed must be a positive number of cells per second");
  }
  ReaderSettings settings = options.reader;
  if (!options.prefetch) settings.prefetch_threads = 0;
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(svc_file, settings));
  const double speed = options.cells_per_second * cell_length(reader->info());
  std::vector<Event> events = cell_entries(*reader, path, speed);
  if (options.max_steps > 0 && events.size() > static_cast<size_t>(options.max_steps)) {
    events.resize(static_cast<size_t>(options.max_steps));
  }

  ReplayResult result;
  result.prefetch = options.prefetch && settings.prefetch_threads > 0;
  if (events.empty()) return result;
  if (result.prefetch && options.warm_start) {
    SVC_RETURN_IF_ERROR(reader->set_viewer(events[0].position, events[0].velocity));
    reader->wait_for_prefetch(std::chrono::minutes(10));
  }
  const ReaderStats at_start = reader->stats();
  uint64_t face_requests = 0, face_hits = 0;
  const Clock::time_point start = Clock::now();
  double skipped = 0;  // idle seconds not waited out
  for (const Event& event : events) {
    // Let time pass until the viewer enters this cell.
    const double remaining = event.time - (seconds_since(start) + skipped);
    if (remaining > 0) {
      if (options.realtime) {
        std::this_thread::sleep_for(std::chrono::duration<double>(remaining));
      } else if (result.prefetch) {
        const Clock::time_point before = Clock::now();
        if (reader->wait_for_prefetch(
                std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::duration<double>(remaining)))) {
          skipped += std::max(0.0, remaining - seconds_since(before));
        }
      } else {
        skipped += remaining;  // nothing runs in the background
      }
    }
    if (result.prefetch) SVC_RETURN_IF_ERROR(reader->set_viewer(event.position, event.velocity));
    const ReaderStats before = reader->stats();
    const Clock::time_point t0 = Clock::now();
    auto cube = reader->decode_cube(event.cell);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (!cube.ok()) return cube.status();
    const ReaderStats after = reader->stats();
    result.latency_ms.push_back(ms);
    const uint64_t decoded = (after.face_cache.misses - before.face_cache.misses) +
                             (after.face_cache.in_flight_waits - before.face_cache.in_flight_waits);
    if (decoded > 0) ++result.steps_waiting;
    face_requests += kFaceCount;
    face_hits += after.face_cache.hits - before.face_cache.hits;
  }
  result.wall_seconds = seconds_since(start);
  result.steps = static_cast<int>(events.size());
  result.simulated_seconds = events.back().time - events.front().time;
  result.p50_ms = percentile(result.latency_ms, 0.50);
  result.p99_ms = percentile(result.latency_ms, 0.99);
  result.max_ms = percentile(result.latency_ms, 1.0);
  double sum = 0;
  for (double v : result.latency_ms) sum += v;
  result.mean_ms = sum / result.latency_ms.size();
  result.face_hit_rate = face_requests ? static_cast<double>(face_hits) / face_requests : 0;
  result.stats = reader->stats();
  const CacheCounters& c = result.stats.coefficient_cache;
  const uint64_t lookups = (c.hits - at_start.coefficient_cache.hits) +
                           (c.misses - at_start.coefficient_cache.misses) +
                           (c.in_flight_waits - at_start.coefficient_cache.in_flight_waits);
  result.coefficient_hit_rate = lookups ? static_cast<double>(c.hits - at_start.coefficient_cache.hits) / lookups
                                        : -1;
  const CacheCounters& r = result.stats.reference_cache;
  result.memory_held = result.stats.face_cache.bytes_held + c.bytes_held + r.bytes_held;
  result.memory_peak = result.stats.face_cache.peak_bytes + c.peak_bytes + r.peak_bytes;
  return result;
}

}  // namespace svc::walkthrough
