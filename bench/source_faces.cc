#include "source_faces.h"

#include "bench_util.h"
#include "svc/metrics.h"

namespace svc::bench {

Result<SourceFaces> load_sources(const std::filesystem::path& db_dir, int threads) {
  SourceFaces source;
  SVC_ASSIGN_OR_RETURN(source.manifest, load_manifest(db_dir));
  source.faces.resize(source.manifest.cells.size() * kFaceCount);
  SVC_RETURN_IF_ERROR(parallel_for(source.faces.size(), threads, [&](size_t i) -> Status {
    SVC_ASSIGN_OR_RETURN(FaceData data, load_face(source.manifest, i / kFaceCount, kAllFaces[i % kFaceCount]));
    source.faces[i] = std::move(data.color);
    return Status::Ok();
  }));
  return source;
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
