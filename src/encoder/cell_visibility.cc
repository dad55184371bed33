#include "encoder/cell_visibility.h"

#include "common/parallel.h"

namespace svc {

Result<CellVisibility> CellVisibility::load(const DatabaseManifest& manifest,
                                            const std::vector<std::optional<size_t>>& sources, int threads) {
  CellVisibility loaded;
  loaded.cubes_.resize(sources.size());
  loaded.present_.assign(sources.size(), 0);
  SVC_RETURN_IF_ERROR(parallel_for(sources.size(), threads, [&](size_t c) -> Status {
    if (!sources[c]) return Status::Ok();
    SVC_ASSIGN_OR_RETURN(const CellSource source, read_cell(manifest, *sources[c]));
    for (Face face : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(FaceData data, load_face(manifest, source, face));
      if (!add_face_samples(&loaded.cubes_[c], face, source.faces[static_cast<int>(face)].camera,
                            manifest.face_width, manifest.face_height, data.depth)) {
        return Status(ErrorCode::kBadInput,
                      face_label(source.index, face) + ": depth does not have the face size " +
                          std::to_string(manifest.face_width) + "x" + std::to_string(manifest.face_height));
      }
    }
    loaded.present_[c] = 1;
    return Status::Ok();
  }));
  return loaded;
}

VisibilityTable CellVisibility::empty_table() const {
  VisibilityTable table(cubes_.size());
  for (uint32_t c = 0; c < cubes_.size(); ++c) table.set_samples(c, sample_count(cubes_[c]));
  return table;
}

void CellVisibility::measure(const std::vector<std::pair<uint32_t, uint32_t>>& pairs, int threads,
                             VisibilityTable* table) const {
  auto usable = [&](const std::pair<uint32_t, uint32_t>& pair) {
    return pair.first < cubes_.size() && pair.second < cubes_.size() && present_[pair.first] &&
           present_[pair.second];
  };
  std::vector<std::vector<uint64_t>> seen(pairs.size());
  // Cannot fail: every item returns Ok.
  (void)parallel_for(pairs.size(), threads, [&](size_t p) -> Status {
    if (usable(pairs[p])) seen[p] = seen_by(cubes_[pairs[p].first], cubes_[pairs[p].second]);
    return Status::Ok();
  });
  for (size_t p = 0; p < pairs.size(); ++p) {
    if (usable(pairs[p])) table->set_seen(pairs[p].first, pairs[p].second, std::move(seen[p]));
  }
}

Result<VisibilityTable> measure_visibility(const DatabaseManifest& manifest,
                                           const std::vector<std::optional<size_t>>& sources,
                                           const std::vector<std::pair<uint32_t, uint32_t>>& pairs, int threads) {
  SVC_ASSIGN_OR_RETURN(CellVisibility cells, CellVisibility::load(manifest, sources, threads));
  VisibilityTable table = cells.empty_table();
  cells.measure(pairs, threads, &table);
  return table;
}

}  // namespace svc
