#include "encoder/cell_visibility.h"

#include "common/parallel.h"
#include "spatial/visibility.h"

namespace svc {

Result<VisibilityTable> measure_visibility(const DatabaseManifest& manifest,
                                           const std::vector<std::optional<size_t>>& sources,
                                           const std::vector<std::pair<uint32_t, uint32_t>>& pairs, int threads) {
  std::vector<CubeSamples> cubes(sources.size());
  SVC_RETURN_IF_ERROR(parallel_for(sources.size(), threads, [&](size_t c) -> Status {
    if (!sources[c]) return Status::Ok();
    for (Face face : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(FaceData data, load_face(manifest, *sources[c], face));
      const CellSource& source = manifest.cells[*sources[c]];
      if (!add_face_samples(&cubes[c], face, source.faces[static_cast<int>(face)].camera, manifest.face_width,
                            manifest.face_height, data.depth)) {
        return Status(ErrorCode::kBadInput,
                      face_label(source.index, face) + ": depth does not have the face size " +
                          std::to_string(manifest.face_width) + "x" + std::to_string(manifest.face_height));
      }
    }
    return Status::Ok();
  }));
  std::vector<std::vector<uint64_t>> seen(pairs.size());
  SVC_RETURN_IF_ERROR(parallel_for(pairs.size(), threads, [&](size_t p) -> Status {
    const auto [cell, reference] = pairs[p];
    if (sources.at(cell) && sources.at(reference)) seen[p] = seen_by(cubes[cell], cubes[reference]);
    return Status::Ok();
  }));
  VisibilityTable table(sources.size());
  for (uint32_t c = 0; c < sources.size(); ++c) table.set_samples(c, sample_count(cubes[c]));
  for (size_t p = 0; p < pairs.size(); ++p) {
    if (sources[pairs[p].first] && sources[pairs[p].second]) {
      table.set_seen(pairs[p].first, pairs[p].second, std::move(seen[p]));
    }
  }
  return table;
}

}  // namespace svc
