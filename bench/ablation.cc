// SPDX-License-Identifier: BSD-2-Clause
// The gain of each coding tool on its own: svc re-encoded at its own quality settings
// with one tool switched off, scored like every other run, and compared by BD-rate.
#include "bd_rate.h"
#include "bench_runner.h"

namespace svc::bench {

namespace {

std::vector<RatePoint> psnr_y_points(const std::vector<QualityPoint>& points) {
  std::vector<RatePoint> rate;
  for (const QualityPoint& p : points) rate.push_back({double(p.bytes), p.psnr_y});
  return rate;
}

CodingTools all_tools_off() {
  CodingTools tools;
  for (const std::string& name : coding_tool_names()) (void)disable_coding_tool(&tools, name);
  return tools;
}

}  // namespace

Result<std::vector<AblationRow>> Bench::run_ablation(const CodecResult& svc) {
  std::vector<std::string> names = coding_tool_names();
  names.push_back("all");
  std::vector<AblationRow> rows;
  for (const std::string& name : names) {
    AblationRow row;
    row.tool = name;
    for (const QualityPoint& reference : svc.points) {
      EncoderSettings settings = default_encoder_settings();
      settings.quality = reference.setting;
      if (name == "all") {
        settings.tools = all_tools_off();
      } else {
        SVC_RETURN_IF_ERROR(disable_coding_tool(&settings.tools, name));
      }
      SVC_ASSIGN_OR_RETURN(SvcRun run,
                           run_svc(settings, 1, "ablation-" + name + "-q" + std::to_string(reference.setting)));
      log_point("svc without " + name, run.point);
      row.encode_seconds += run.point.encode_seconds;
      row.points.push_back(run.point);
    }
    if (auto bd = bd_rate(psnr_y_points(svc.points), psnr_y_points(row.points))) row.bd_rate_y = bd->ratio - 1;
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace svc::bench
