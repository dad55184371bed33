// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/cube_padding_map.h"

#include <algorithm>
#include <compare>
#include <cstring>
#include <map>
#include <mutex>

namespace svc::codec::cube_padding_internal {

namespace {

// One axis of a tap at 1/16 position `p16` of an n-sample axis: the block's first column
// (or row), at most n - 2 so that the block stays inside, and the weights of its two
// columns. The reference's taps at ix and ix + 1 are clamped to 0..n-1 each and their
// weights added onto the block column they land on.
struct AxisTaps {
  int first;
  std::array<int, 2> weights;
};

AxisTaps axis_taps(int p16, int n) {
  const int i = p16 >> 4, f = p16 & 15;
  const int i0 = std::clamp(i, 0, n - 1), i1 = std::clamp(i + 1, 0, n - 1);
  const int first = std::min(i0, n - 2);
  // i0 and i1 are each first or first + 1, so the two weights add up to 16.
  const int weight_first = (i0 == first ? 16 - f : 0) + (i1 == first ? f : 0);
  return {first, {weight_first, 16 - weight_first}};
}

// Appends border sample `offset` of the padded plane, read from `face` at `source`, to
// the map: onto the last run when it continues it, else as a new run.
void append(BorderMap* map, size_t offset, const BorderSource& source, int n) {
  if (map->runs.empty() || map->runs.back().face != source.face ||
      map->runs.back().offset + map->runs.back().count != offset) {
    map->runs.push_back({offset, 0, source.face});
  }
  ++map->runs.back().count;
  const AxisTaps x = axis_taps(source.x16, n), y = axis_taps(source.y16, n);
  map->indices.push_back(static_cast<uint32_t>(static_cast<size_t>(y.first) * n + x.first));
  map->weights.push_back({static_cast<uint8_t>(x.weights[0]), static_cast<uint8_t>(x.weights[1]),
                          static_cast<uint8_t>(y.weights[0]), static_cast<uint8_t>(y.weights[1])});
}

struct MapKey {
  int face, n, border;
  auto operator<=>(const MapKey&) const = default;
};

struct MapCache {
  std::mutex mutex;
  std::map<MapKey, std::shared_ptr<const BorderMap>> maps;
  size_t bytes = 0;
};

// Never destroyed, so that padding from a thread still running at exit stays valid.
MapCache& map_cache() {
  static MapCache* cache = new MapCache();
  return *cache;
}

size_t map_bytes(const BorderMap& map) {
  return map.indices.size() * sizeof(uint32_t) + map.weights.size() * sizeof(dsp::BilinearWeights) +
         map.runs.size() * sizeof(BorderRun);
}

}  // namespace

BorderMap build_border_map(int face, int n, int border) {
  BorderMap map;
  const size_t size = static_cast<size_t>(n) + 2 * static_cast<size_t>(border);
  const size_t samples = size * size - static_cast<size_t>(n) * n;
  map.indices.reserve(samples);
  map.weights.reserve(samples);
  for (int j = -border; j < n + border; ++j) {
    const bool row_inside = j >= 0 && j < n;
    for (int i = -border; i < n + border; ++i) {
      if (row_inside && i == 0) {  // the face itself is copied, not mapped
        i = n - 1;
        continue;
      }
      append(&map, static_cast<size_t>(j + border) * size + static_cast<size_t>(i + border),
             border_source(face, n, i, j), n);
    }
  }
  return map;
}

std::shared_ptr<const BorderMap> cached_border_map(int face, int n, int border) {
  MapCache& cache = map_cache();
  const MapKey key{face, n, border};
  {
    std::lock_guard<std::mutex> lock(cache.mutex);
    const auto found = cache.maps.find(key);
    if (found != cache.maps.end()) return found->second;
  }
  // Built without the lock, so that threads padding other geometries do not wait; a
  // thread racing on the same key builds the same map, and the first one stored stays.
  auto map = std::make_shared<const BorderMap>(build_border_map(face, n, border));
  std::lock_guard<std::mutex> lock(cache.mutex);
  const auto found = cache.maps.find(key);
  if (found != cache.maps.end()) return found->second;
  // Maps in use stay alive with their callers; the newest is kept even on its own over
  // the byte bound (it is a fraction of the planes it pads).
  if (cache.maps.size() >= kMaxCachedBorderMaps || cache.bytes + map_bytes(*map) > kMaxCachedBorderMapBytes) {
    cache.maps.clear();
    cache.bytes = 0;
  }
  cache.maps.emplace(key, map);
  cache.bytes += map_bytes(*map);
  return map;
}

size_t cached_border_map_count() {
  MapCache& cache = map_cache();
  std::lock_guard<std::mutex> lock(cache.mutex);
  return cache.maps.size();
}

void pad_plane(const FacePlanes& planes, int face, int n, int border, std::vector<uint8_t>* out) {
  if (border == 0) {
    out->assign(planes[face]->begin(), planes[face]->end());
    return;
  }
  if (n < kMinMappedPlaneSide || n > kMaxMappedPlaneSide) {
    pad_plane_reference(planes, face, n, border, out);
    return;
  }
  const std::shared_ptr<const BorderMap> map = cached_border_map(face, n, border);
  const size_t side = static_cast<size_t>(n), size = side + 2 * static_cast<size_t>(border);
  out->resize(size * size);
  uint8_t* inside = out->data() + static_cast<size_t>(border) * size + border;
  for (size_t j = 0; j < side; ++j) std::memcpy(inside + j * size, planes[face]->data() + j * side, side);
  // No branches per sample: the edge clamp is in the weights, so every sample reads a
  // whole 2 x 2 block.
  const auto sample_run = dsp::get_dsp().pad_sample_run;
  size_t tap = 0;
  for (const BorderRun& run : map->runs) {
    if (planes[run.face] == nullptr) {
      std::memset(out->data() + run.offset, 0, run.count);
      tap += run.count;
      continue;
    }
    sample_run(planes[run.face]->data(), static_cast<ptrdiff_t>(side), map->indices.data() + tap,
               map->weights.data() + tap, static_cast<int>(run.count), out->data() + run.offset);
    tap += run.count;
  }
}

}  // namespace svc::codec::cube_padding_internal
