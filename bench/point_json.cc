// SPDX-License-Identifier: BSD-2-Clause
#include "point_json.h"

namespace svc::bench {

using json = nlohmann::ordered_json;

json point_json(const QualityPoint& p) {
  json j;
  j["setting_name"] = p.setting_name;
  j["setting"] = p.setting;
  j["bytes"] = p.bytes;
  j["compression_ratio"] = p.compression_ratio;
  j["bits_per_pixel"] = p.bits_per_pixel;
  j["psnr_rgb"] = p.psnr_rgb;
  j["psnr_y"] = p.psnr_y;
  j["ssim"] = p.ssim;
  j["encode_seconds"] = p.encode_seconds;
  j["decode_seconds"] = p.decode_seconds;
  if (p.b_face_bytes) {
    j["b_face_bytes"] = p.b_face_bytes;
    j["b_face_psnr_y"] = p.b_face_psnr_y;
  }
  return j;
}

Result<QualityPoint> point_from_json(const json& j) {
  if (!j.is_object() || !j.contains("bytes") || !j["bytes"].is_number_unsigned() || !j.contains("psnr_y") ||
      !j["psnr_y"].is_number()) {
    return Status(ErrorCode::kBadInput, "a quality point lacks bytes or psnr_y");
  }
  QualityPoint p;
  p.setting_name = j.value("setting_name", "");
  p.setting = j.value("setting", 0);
  p.bytes = j["bytes"].get<uint64_t>();
  p.compression_ratio = j.value("compression_ratio", 0.0);
  p.bits_per_pixel = j.value("bits_per_pixel", 0.0);
  p.psnr_rgb = j.value("psnr_rgb", 0.0);
  p.psnr_y = j["psnr_y"].get<double>();
  p.ssim = j.value("ssim", 0.0);
  p.encode_seconds = j.value("encode_seconds", 0.0);
  p.decode_seconds = j.value("decode_seconds", 0.0);
  p.b_face_bytes = j.value("b_face_bytes", uint64_t{0});
  p.b_face_psnr_y = j.value("b_face_psnr_y", 0.0);
  return p;
}

}  // namespace svc::bench
