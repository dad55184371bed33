// SPDX-License-Identifier: BSD-2-Clause
#include "support/svc_measure.h"

#include <chrono>

#include "svc/metrics.h"
#include "svc/reader.h"

namespace svc::bench {

Result<SvcMeasurement> measure_svc(const SceneFaces& scene, const EncoderSettings& settings) {
  const auto out = scene.work_dir / "measure.svc";
  const auto t0 = std::chrono::steady_clock::now();
  SvcMeasurement m;
  SVC_ASSIGN_OR_RETURN(m.summary, encode_database(scene.db_dir, out, settings));
  m.point.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.point.setting = m.summary.qindex;
  m.point.bytes = static_cast<double>(m.summary.file_bytes);
  SVC_ASSIGN_OR_RETURN(auto reader, Reader::open(out));
  SquaredError error;
  for (size_t c = 0; c < scene.cells.size(); ++c) {
    for (Face face : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(ImageRGB8 decoded, reader->decode_face(scene.cells[c], face));
      SVC_ASSIGN_OR_RETURN(SquaredError e, luma_squared_error(scene.face(c, face), decoded));
      error.add(e);
    }
  }
  m.point.psnr_y = error.psnr();
  std::error_code ec;
  std::filesystem::remove(out, ec);
  return m;
}

Result<std::vector<SvcMeasurement>> sweep_svc(const SceneFaces& scene, EncoderSettings settings,
                                              const std::vector<int>& qindices) {
  std::vector<SvcMeasurement> out;
  for (int q : qindices) {
    settings.qindex = q;
    SVC_ASSIGN_OR_RETURN(SvcMeasurement m, measure_svc(scene, settings));
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace svc::bench
