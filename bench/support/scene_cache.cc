// SPDX-License-Identifier: BSD-2-Clause
#include "support/scene_cache.h"

#include <random>

#include "database/database.h"

namespace svc::bench {

Result<std::unique_ptr<SceneFaces>> SceneFaces::generate(const samples::SceneOptions& options) {
  auto scene = std::make_unique<SceneFaces>();
  scene->work_dir =
      std::filesystem::temp_directory_path() / ("svc-bench-" + std::to_string(std::random_device{}()));
  scene->db_dir = scene->work_dir / "db";
  SVC_RETURN_IF_ERROR(samples::generate_scene(options, scene->db_dir));
  SVC_ASSIGN_OR_RETURN(DatabaseManifest manifest, load_manifest(scene->db_dir));
  scene->dims = {manifest.grid.dims[0], manifest.grid.dims[1], manifest.grid.dims[2]};
  for (size_t c = 0; c < manifest.cells.size(); ++c) {
    scene->cells.push_back(manifest.cells[c].index);
    for (Face face : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(FaceData data, load_face(manifest, c, face));
      scene->faces_.push_back(std::move(data.color));
    }
  }
  return scene;
}

SceneFaces::~SceneFaces() {
  std::error_code ec;
  std::filesystem::remove_all(work_dir, ec);
}

size_t SceneFaces::ordinal_of(const CellIndex& cell) const {
  for (size_t c = 0; c < cells.size(); ++c) {
    if (cells[c] == cell) return c;
  }
  return 0;
}

baseline::DatabaseFrames SceneFaces::baseline_frames() const {
  baseline::DatabaseFrames input;
  input.dims = dims;
  input.cells = cells;
  input.width = faces_.empty() ? 0 : faces_[0].width;
  input.height = faces_.empty() ? 0 : faces_[0].height;
  input.load = [this](CellIndex cell, Face f) -> Result<ImageRGB8> { return face(ordinal_of(cell), f); };
  return input;
}

}  // namespace svc::bench
