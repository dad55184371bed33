// SPDX-License-Identifier: BSD-2-Clause
// A generated sample scene held in memory for the benchmarks: its source faces, its
// cells, and a work folder removed when the object goes away.
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "baseline/baseline.h"
#include "scene/scene.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc::bench {

class SceneFaces {
 public:
  // Generates `options` into a fresh temporary folder and loads every face's color.
  static Result<std::unique_ptr<SceneFaces>> generate(const samples::SceneOptions& options);
  ~SceneFaces();

  std::filesystem::path work_dir;  // scratch space for encoded files
  std::filesystem::path db_dir;    // the svc-input database
  std::array<int, 3> dims{1, 1, 1};
  std::vector<CellIndex> cells;  // manifest order (y, z, x)

  const ImageRGB8& face(size_t cell, Face f) const { return faces_[cell * kFaceCount + static_cast<int>(f)]; }
  size_t ordinal_of(const CellIndex& cell) const;
  // The same faces as input for the libavcodec baseline.
  baseline::DatabaseFrames baseline_frames() const;

 private:
  std::vector<ImageRGB8> faces_;
};

}  // namespace svc::bench
