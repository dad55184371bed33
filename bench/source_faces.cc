// SPDX-License-Identifier: BSD-2-Clause
#include "source_faces.h"

#include <algorithm>
#include <cmath>

#include "bench_util.h"
#include "svc/metrics.h"

namespace svc::bench {

Result<SourceFaces> load_sources(const std::filesystem::path& db_dir, int threads) {
  SourceFaces source;
  SVC_ASSIGN_OR_RETURN(source.manifest, load_manifest(db_dir));
  source.faces.resize(source.manifest.cells.size() * kFaceCount);
  std::vector<uint64_t> background(source.faces.size());
  SVC_RETURN_IF_ERROR(parallel_for(source.faces.size(), threads, [&](size_t i) -> Status {
    SVC_ASSIGN_OR_RETURN(FaceData data, load_face(source.manifest, i / kFaceCount, kAllFaces[i % kFaceCount]));
    source.faces[i] = std::move(data.color);
    background[i] = std::count_if(data.depth.begin(), data.depth.end(), [](float z) { return std::isinf(z); });
    return Status::Ok();
  }));
  for (uint64_t b : background) source.background_pixels += b;
  return source;
}

namespace {

// BT.601 full-range luma of an RGB pixel, as the scores use it.
double luma(const uint8_t* p) { return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]; }

struct LumaSums {
  double sum = 0, sum_squares = 0, gradient = 0;
  uint64_t pixels = 0, pairs = 0;
};

LumaSums luma_sums(const ImageRGB8& face) {
  LumaSums s;
  for (int y = 0; y < face.height; ++y) {
    const uint8_t* row = &face.pixels[static_cast<size_t>(y) * face.width * 3];
    for (int x = 0; x < face.width; ++x) {
      const double v = luma(row + 3 * x);
      s.sum += v;
      s.sum_squares += v * v;
      if (x > 0) s.gradient += std::abs(v - luma(row + 3 * (x - 1)));
    }
  }
  s.pixels = static_cast<uint64_t>(face.width) * face.height;
  s.pairs = static_cast<uint64_t>(face.width - 1) * face.height;
  return s;
}

}  // namespace

ContentStats content_stats(const SourceFaces& source, int threads) {
  std::vector<LumaSums> per_face(source.faces.size());
  (void)parallel_for(per_face.size(), threads, [&](size_t i) -> Status {
    per_face[i] = luma_sums(source.faces[i]);
    return Status::Ok();
  });
  LumaSums total;
  for (const LumaSums& s : per_face) {
    total.sum += s.sum;
    total.sum_squares += s.sum_squares;
    total.gradient += s.gradient;
    total.pixels += s.pixels;
    total.pairs += s.pairs;
  }
  ContentStats stats;
  if (total.pixels == 0) return stats;
  stats.mean_luma = total.sum / total.pixels;
  stats.luma_contrast =
      std::sqrt(std::max(0.0, total.sum_squares / total.pixels - stats.mean_luma * stats.mean_luma));
  stats.mean_gradient = total.pairs ? total.gradient / total.pairs : 0;
  stats.background_share = static_cast<double>(source.background_pixels) / total.pixels;
  return stats;
}

Result<Score> score_faces(const std::vector<std::pair<const ImageRGB8*, const ImageRGB8*>>& pairs, int threads) {
  std::vector<SquaredError> rgb(pairs.size()), luma(pairs.size());
  std::vector<double> ssim(pairs.size());
  SVC_RETURN_IF_ERROR(parallel_for(pairs.size(), threads, [&](size_t i) -> Status {
    SVC_ASSIGN_OR_RETURN(rgb[i], rgb_squared_error(*pairs[i].first, *pairs[i].second));
    SVC_ASSIGN_OR_RETURN(luma[i], luma_squared_error(*pairs[i].first, *pairs[i].second));
    SVC_ASSIGN_OR_RETURN(ssim[i], luma_ssim(*pairs[i].first, *pairs[i].second));
    return Status::Ok();
  }));
  SquaredError total_rgb, total_luma;
  double ssim_sum = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    total_rgb.add(rgb[i]);
    total_luma.add(luma[i]);
    ssim_sum += ssim[i];
  }
  Score score;
  score.psnr_rgb = total_rgb.psnr();
  score.psnr_y = total_luma.psnr();
  score.ssim = pairs.empty() ? 0 : ssim_sum / pairs.size();
  return score;
}

}  // namespace svc::bench
