// SPDX-License-Identifier: BSD-2-Clause
#include "encoder/cell_visibility.h"

#include <algorithm>
#include <map>
#include <tuple>

#include "common/parallel.h"
#include "encoder/coding_pipeline.h"

namespace svc {

namespace {

// Cells a batch measures together: enough for the threads to share, few enough that
// the batch's cubes stay a small part of the budget.
constexpr size_t kBatchCells = 16;

Result<CubeSamples> load_cube(const DatabaseManifest& manifest, size_t source_cell) {
  SVC_ASSIGN_OR_RETURN(const CellSource source, read_cell(manifest, source_cell));
  CubeSamples cube;
  for (Face face : kAllFaces) {
    SVC_ASSIGN_OR_RETURN(const std::vector<float> depth, load_face_depth(manifest, source, face));
    if (!add_face_samples(&cube, face, source.faces[static_cast<int>(face)].camera, manifest.face_width,
                          manifest.face_height, depth)) {
      return Status(ErrorCode::kBadInput, face_label(source.index, face) + ": depth does not have the face size " +
                                              std::to_string(manifest.face_width) + "x" +
                                              std::to_string(manifest.face_height));
    }
  }
  return cube;
}

uint64_t cube_bytes(const CubeSamples& cube) {
  uint64_t bytes = sizeof(CubeSamples);
  for (const std::vector<float>& depth : cube.depth) bytes += depth.capacity() * sizeof(float);
  return bytes;
}

}  // namespace

VisibilityMeter::VisibilityMeter(const DatabaseManifest& manifest, std::vector<std::optional<size_t>> sources,
                                 int threads, uint64_t cache_bytes)
    : manifest_(manifest), sources_(std::move(sources)), threads_(threads), cache_bytes_(cache_bytes) {}

VisibilityTable VisibilityMeter::empty_table() const {
  const size_t step = kVisibilitySampleStep;
  const size_t per_face = ((static_cast<size_t>(manifest_.face_width) + step - 1) / step) *
                          ((static_cast<size_t>(manifest_.face_height) + step - 1) / step);
  VisibilityTable table(sources_.size());
  for (uint32_t c = 0; c < sources_.size(); ++c) table.set_samples(c, sources_[c] ? kFaceCount * per_face : 0);
  return table;
}

Status VisibilityMeter::measure(const std::vector<std::pair<uint32_t, uint32_t>>& pairs, VisibilityTable* table) {
  const auto held = [&](uint32_t c) { return c < sources_.size() && sources_[c].has_value(); };
  std::map<uint32_t, std::vector<uint32_t>> references;
  for (const auto& [cell, reference] : pairs) {
    if (held(cell) && held(reference)) references[cell].push_back(reference);
  }
  std::vector<uint32_t> order;
  for (const auto& entry : references) order.push_back(entry.first);
  const auto grid_order = [&](uint32_t c) {
    const CellIndex& i = manifest_.cells[*sources_[c]].index;
    return std::make_tuple(i.y, i.z, i.x, c);
  };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return grid_order(a) < grid_order(b); });

  for (size_t begin = 0; begin < order.size(); begin += kBatchCells) {
    const std::vector<uint32_t> batch(order.begin() + static_cast<std::ptrdiff_t>(begin),
                                      order.begin() +
                                          static_cast<std::ptrdiff_t>(std::min(order.size(), begin + kBatchCells)));
    ++batch_;
    std::vector<uint32_t> needed = batch;
    for (uint32_t c : batch) needed.insert(needed.end(), references[c].begin(), references[c].end());
    std::sort(needed.begin(), needed.end());
    needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
    SVC_RETURN_IF_ERROR(load_missing(needed));
    for (uint32_t c : needed) cache_.at(c).last_batch = batch_;

    std::vector<std::vector<std::pair<uint32_t, std::vector<uint64_t>>>> seen(batch.size());
    // Cannot fail: every item returns Ok.
    (void)parallel_for(batch.size(), threads_, [&](size_t i) -> Status {
      const CubeSamples& current = *cache_.at(batch[i]).samples;
      for (uint32_t reference : references[batch[i]])
        seen[i].emplace_back(reference, seen_by(current, *cache_.at(reference).samples));
      return Status::Ok();
    });
    for (size_t i = 0; i < batch.size(); ++i) table->set_seen(batch[i], seen[i]);
    evict_to_budget();
  }
  return Status::Ok();
}

Status VisibilityMeter::load_missing(const std::vector<uint32_t>& cells) {
  std::vector<uint32_t> missing;
  for (uint32_t c : cells) {
    if (!cache_.contains(c)) missing.push_back(c);
  }
  std::vector<std::shared_ptr<const CubeSamples>> loaded(missing.size());
  SVC_RETURN_IF_ERROR(parallel_for(missing.size(), threads_, [&](size_t i) -> Status {
    SVC_ASSIGN_OR_RETURN(CubeSamples cube, load_cube(manifest_, *sources_[missing[i]]));
    loaded[i] = std::make_shared<const CubeSamples>(std::move(cube));
    return Status::Ok();
  }));
  for (size_t i = 0; i < missing.size(); ++i) {
    const uint64_t bytes = cube_bytes(*loaded[i]);
    cache_[missing[i]] = CachedCube{std::move(loaded[i]), bytes, batch_};
    held_bytes_ += bytes;
  }
  peak_bytes_ = std::max(peak_bytes_, held_bytes_);
  return Status::Ok();
}

// Drops the least recently used cubes until the cache fits its budget; ties (cubes of
// one batch) go by cell ordinal, though which goes first never changes a result.
void VisibilityMeter::evict_to_budget() {
  if (held_bytes_ <= cache_bytes_) return;
  std::vector<std::pair<uint64_t, uint32_t>> by_age;
  for (const auto& [cell, cube] : cache_) by_age.emplace_back(cube.last_batch, cell);
  std::sort(by_age.begin(), by_age.end());
  for (const auto& [batch, cell] : by_age) {
    if (held_bytes_ <= cache_bytes_) break;
    held_bytes_ -= cache_.at(cell).bytes;
    cache_.erase(cell);
  }
}

Result<VisibilityTable> measure_visibility(const DatabaseManifest& manifest,
                                           const std::vector<std::optional<size_t>>& sources,
                                           const std::vector<std::pair<uint32_t, uint32_t>>& pairs, int threads) {
  VisibilityMeter meter(manifest, sources, threads, reference_cache_bytes());
  VisibilityTable table = meter.empty_table();
  SVC_RETURN_IF_ERROR(meter.measure(pairs, &table));
  return table;
}

}  // namespace svc
