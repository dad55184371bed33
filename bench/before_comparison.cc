// SPDX-License-Identifier: BSD-2-Clause
#include "before_comparison.h"

#include <fstream>

#include <nlohmann/json.hpp>

#include "bd_rate.h"
#include "point_json.h"

namespace svc::bench {

namespace {

using json = nlohmann::ordered_json;

Status not_results(const std::filesystem::path& path, const std::string& why) {
  return Status(ErrorCode::kInvalidArgument, "--before " + path.string() + ": " + why);
}

std::optional<double> bd(const std::vector<QualityPoint>& before, const std::vector<QualityPoint>& now,
                         bool b_faces) {
  std::vector<RatePoint> a, b;
  for (const QualityPoint& p : before) {
    a.push_back(b_faces ? RatePoint{double(p.b_face_bytes), p.b_face_psnr_y}
                        : RatePoint{double(p.bytes), p.psnr_y});
  }
  for (const QualityPoint& p : now) {
    b.push_back(b_faces ? RatePoint{double(p.b_face_bytes), p.b_face_psnr_y}
                        : RatePoint{double(p.bytes), p.psnr_y});
  }
  const auto result = bd_rate(a, b);
  return result ? std::optional<double>(result->ratio - 1) : std::nullopt;
}

bool records_b_faces(const std::vector<QualityPoint>& points) {
  for (const QualityPoint& p : points) {
    if (p.b_face_bytes == 0) return false;
  }
  return !points.empty();
}

}  // namespace

Result<std::vector<QualityPoint>> load_svc_points(const std::filesystem::path& results_json) {
  std::ifstream in(results_json);
  if (!in) return Status(ErrorCode::kIoError, "--before: cannot read " + results_json.string());
  const json j = json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object() || !j.contains("codecs") || !j["codecs"].is_array()) {
    return not_results(results_json, "not a results.json of svc bench");
  }
  std::vector<QualityPoint> points;
  for (const json& codec : j["codecs"]) {
    if (!codec.is_object() || codec.value("name", "") != "svc" || !codec.contains("points")) continue;
    for (const json& p : codec["points"]) {
      Result<QualityPoint> point = point_from_json(p);
      if (!point.ok()) return not_results(results_json, "an svc point lacks bytes or psnr_y");
      points.push_back(*point);
    }
  }
  if (points.size() < 2) return not_results(results_json, "fewer than two svc points");
  return points;
}

BeforeComparison compare_with_before(const std::filesystem::path& results_json,
                                     const std::vector<QualityPoint>& before,
                                     const std::vector<QualityPoint>& now) {
  BeforeComparison comparison;
  comparison.results = results_json.string();
  comparison.bd_rate_y = bd(before, now, false);
  if (records_b_faces(before) && records_b_faces(now)) comparison.b_faces_bd_rate = bd(before, now, true);
  return comparison;
}

}  // namespace svc::bench
