// SPDX-License-Identifier: BSD-2-Clause
#include "anchor_cache.h"

#include <cstdio>
#include <fstream>
#include <system_error>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "baseline/baseline.h"
#include "common/bytes.h"
#include "point_json.h"
#include "settings_search.h"

namespace svc::bench {

namespace {

using json = nlohmann::ordered_json;

constexpr const char* kFormat = "svc-anchor-cache";

std::string hex64(uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

// Two CRC-32s of different starting values: 64 bits, plenty against accidental collisions
// of a few thousand entries (the key text in the entry settles any that happen).
uint64_t hash_bytes(std::span<const uint8_t> bytes, uint64_t previous) {
  const uint32_t a = crc32_of(bytes, static_cast<uint32_t>(previous));
  const uint32_t b = crc32_of(bytes, static_cast<uint32_t>(previous >> 32) ^ 0x9E3779B9u);
  return (static_cast<uint64_t>(b) << 32) | a;
}

uint64_t hash_text(const std::string& text) {
  return hash_bytes({reinterpret_cast<const uint8_t*>(text.data()), text.size()}, 0);
}

std::filesystem::path entry_path(const std::filesystem::path& dir, const std::string& key) {
  return dir / (hex64(hash_text(key)) + ".json");
}

}  // namespace

std::string source_fingerprint(const SourceFaces& source) {
  uint64_t h = 0;
  for (const ImageRGB8& face : source.faces) {
    const uint32_t size[2] = {static_cast<uint32_t>(face.width), static_cast<uint32_t>(face.height)};
    h = hash_bytes({reinterpret_cast<const uint8_t*>(size), sizeof size}, h);
    h = hash_bytes(face.pixels, h);
  }
  return hex64(h) + "/" + std::to_string(source.faces.size()) + " faces";
}

std::string anchor_cache_key(const std::string& fingerprint, const CodecPlan& plan, bool quick) {
  json key;
  key["faces"] = fingerprint;
  key["codec"] = plan.name;
  key["description"] = plan.description;
  key["command"] = ffmpeg_command(plan, 0, "in", "out", 0);
  key["order"] = static_cast<int>(plan.order);
  key["range"] = {plan.range.lowest, plan.range.highest, plan.range.seeds};
  const SearchTargets targets = default_targets(quick);
  key["targets"] = {targets.psnr_y, targets.tolerance, targets.max_runs};
  key["libraries"] = baseline::library_version();
  return key.dump();
}

std::optional<std::vector<QualityPoint>> load_cached_points(const std::filesystem::path& dir,
                                                            const std::string& key) {
  std::ifstream in(entry_path(dir, key));
  if (!in) return std::nullopt;
  const json entry = json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (entry.is_discarded() || !entry.is_object() || entry.value("format", "") != kFormat ||
      entry.value("key", "") != key || !entry.contains("points") || !entry["points"].is_array()) {
    return std::nullopt;
  }
  std::vector<QualityPoint> points;
  for (const json& p : entry["points"]) {
    Result<QualityPoint> point = point_from_json(p);
    if (!point.ok()) return std::nullopt;
    points.push_back(*point);
  }
  if (points.empty()) return std::nullopt;
  return points;
}

Status store_cached_points(const std::filesystem::path& dir, const std::string& key,
                           const std::vector<QualityPoint>& points) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Status(ErrorCode::kIoError, "anchor cache: cannot create " + dir.string() + ": " + ec.message());
  json entry;
  entry["format"] = kFormat;
  entry["key"] = key;
  json list = json::array();
  for (const QualityPoint& p : points) list.push_back(point_json(p));
  entry["points"] = list;
  const std::filesystem::path path = entry_path(dir, key);
  const std::filesystem::path temporary = path.string() + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << entry.dump(1) << '\n';
    out.close();
    if (!out) return Status(ErrorCode::kIoError, "anchor cache: cannot write " + temporary.string());
  }
  std::filesystem::rename(temporary, path, ec);
  if (ec) return Status(ErrorCode::kIoError, "anchor cache: cannot write " + path.string() + ": " + ec.message());
  return Status::Ok();
}

}  // namespace svc::bench
