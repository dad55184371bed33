// SPDX-License-Identifier: BSD-2-Clause
#include "encoder/shard_fingerprint.h"

#include <algorithm>
#include <string>
#include <vector>

#include "common/file_io.h"

namespace svc {

const char* const kSvcVersion = SVC_VERSION;

namespace {

class Fnv1a64 {
 public:
  void add(std::span<const uint8_t> bytes) {
    for (uint8_t b : bytes) hash_ = (hash_ ^ b) * 0x100000001b3ull;
  }
  void add(const std::string& text) { add({reinterpret_cast<const uint8_t*>(text.data()), text.size() + 1}); }
  void add(uint64_t value) {
    uint8_t bytes[8];
    for (int i = 0; i < 8; ++i) bytes[i] = static_cast<uint8_t>(value >> (8 * i));
    add(bytes);
  }
  uint64_t value() const { return hash_; }

 private:
  uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace

Result<uint64_t> database_fingerprint(const std::filesystem::path& db_dir, const DatabaseManifest& manifest) {
  std::error_code ec;
  const std::filesystem::path manifest_path =
      std::filesystem::is_regular_file(db_dir, ec) ? db_dir : db_dir / "manifest.json";
  SVC_ASSIGN_OR_RETURN(auto file, ReadOnlyFile::open(manifest_path));
  Fnv1a64 hash;
  // In pieces: the manifest of a large database is tens of megabytes.
  std::vector<uint8_t> piece;
  for (uint64_t offset = 0; offset < file->size(); offset += piece.size()) {
    piece.resize(std::min<uint64_t>(file->size() - offset, 1 << 20));
    SVC_RETURN_IF_ERROR(file->read_at(offset, piece));
    hash.add(piece);
  }
  for (size_t c = 0; c < manifest.cells.size(); ++c) {
    SVC_ASSIGN_OR_RETURN(const CellSource cell, read_cell(manifest, c));
    for (const FaceSource& face : cell.faces) {
      for (const std::string* path : {&face.color_path, &face.depth_path}) {
        const uint64_t size = std::filesystem::file_size(resolve_database_path(manifest, *path), ec);
        if (ec) return Status(ErrorCode::kIoError, "cannot read the size of " + *path + ": " + ec.message());
        hash.add(*path);
        hash.add(size);
      }
    }
  }
  return hash.value();
}

std::string shard_settings_text(const EncoderSettings& settings) {
  std::string text;
  auto add = [&](const std::string& option) { text += (text.empty() ? "" : " ") + option; };
  for (const std::string& name : disabled_coding_tools(settings.tools)) add("--disable-tool " + name);
  if (settings.tools.weighted_quant_matrix) add("--quant-matrix weighted");
  if (settings.b_qindex_offset >= 0) add("--b-qindex-offset " + std::to_string(settings.b_qindex_offset));
  if (settings.cube_border_units != EncoderSettings{}.cube_border_units) {
    add("--cube-border " + std::to_string(settings.cube_border_units));
  }
  return text;
}

}  // namespace svc
