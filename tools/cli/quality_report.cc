// SPDX-License-Identifier: BSD-2-Clause
#include "cli/quality_report.h"

#include <mutex>

#include "cli/cli_util.h"
#include "common/parallel.h"

namespace svc::cli {

void QualityReport::add(const QualityReport& other) {
  luma.add(other.luma);
  rgb.add(other.rgb);
  ssim_sum += other.ssim_sum;
  faces += other.faces;
}

Result<QualityReport> measure_cell(Reader& reader, const DatabaseManifest& manifest, size_t ordinal) {
  QualityReport report;
  for (Face face : kAllFaces) {
    SVC_ASSIGN_OR_RETURN(FaceData source, load_face(manifest, ordinal, face));
    SVC_ASSIGN_OR_RETURN(ImageRGB8 decoded, reader.decode_face(manifest.cells[ordinal].index, face));
    SVC_ASSIGN_OR_RETURN(SquaredError luma, luma_squared_error(source.color, decoded));
    SVC_ASSIGN_OR_RETURN(SquaredError rgb, rgb_squared_error(source.color, decoded));
    SVC_ASSIGN_OR_RETURN(double ssim, luma_ssim(source.color, decoded));
    report.luma.add(luma);
    report.rgb.add(rgb);
    report.ssim_sum += ssim;
    ++report.faces;
  }
  return report;
}

Result<QualityReport> measure_database(Reader& reader, const DatabaseManifest& manifest, int threads,
                                       command_line::ProgressBar* bar) {
  // Per-cell results summed in cell order, so the figures do not depend on the threads.
  std::vector<QualityReport> cells(manifest.cells.size());
  std::mutex progress_mutex;
  uint64_t done = 0;
  SVC_RETURN_IF_ERROR(parallel_for(cells.size(), resolve_thread_count(threads), [&](size_t ordinal) -> Status {
    if (!keep_going()) return Status(ErrorCode::kCancelled, "measuring cancelled");
    SVC_ASSIGN_OR_RETURN(cells[ordinal], measure_cell(reader, manifest, ordinal));
    std::lock_guard<std::mutex> lock(progress_mutex);
    bar->update(++done, cells.size());
    return Status::Ok();
  }));
  QualityReport total;
  for (const QualityReport& cell : cells) total.add(cell);
  return total;
}

}  // namespace svc::cli
