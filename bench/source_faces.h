// SPDX-License-Identifier: BSD-2-Clause
// The database's source faces, held in memory, and the scoring of decoded faces against
// them (see svc_bench.h, "Measurement").
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "database/database.h"
#include "svc/status.h"
#include "svc_bench.h"

namespace svc::bench {

struct SourceFaces {
  DatabaseManifest manifest;
  std::vector<ImageRGB8> faces;    // cell ordinal * 6 + face
  uint64_t background_pixels = 0;  // pixels whose depth saw no geometry, over all faces
  const ImageRGB8& face(size_t cell, Face f) const { return faces[cell * kFaceCount + static_cast<size_t>(f)]; }
  std::optional<size_t> ordinal(const CellIndex& cell) const { return find_cell(manifest, cell); }
};

Result<SourceFaces> load_sources(const std::filesystem::path& db_dir, int threads);

// The faces' content statistics (svc_bench.h, ContentStats).
ContentStats content_stats(const SourceFaces& source, int threads);

struct Score {
  double psnr_rgb = 0;  // over the summed squared error of all faces
  double psnr_y = 0;
  double ssim = 0;  // mean over faces
};

// `pairs` holds (source, decoded) per face.
Result<Score> score_faces(const std::vector<std::pair<const ImageRGB8*, const ImageRGB8*>>& pairs, int threads);

}  // namespace svc::bench
