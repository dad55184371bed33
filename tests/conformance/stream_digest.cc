// SPDX-License-Identifier: BSD-2-Clause
#include "conformance/stream_digest.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <span>
#include <vector>

#include <nettle/md5.h>

#include "svc/reader.h"

namespace svc::conformance {
namespace {

class Md5 {
 public:
  Md5() { md5_init(&context_); }
  void update(std::span<const uint8_t> bytes) { md5_update(&context_, bytes.size(), bytes.data()); }
  std::string hex_digest() {
    std::array<uint8_t, MD5_DIGEST_SIZE> digest{};
    md5_digest(&context_, digest.size(), digest.data());
    std::string hex;
    for (uint8_t b : digest) {
      char two[3];
      std::snprintf(two, sizeof two, "%02x", b);
      hex += two;
    }
    return hex;
  }

 private:
  md5_ctx context_;
};

Status hash_depth(Reader& reader, const CellIndex& cell, Face face, Md5& md5) {
  const FileInfo& info = reader.info();
  std::vector<uint16_t> codes(static_cast<size_t>(info.face_width) * info.face_height);
  DepthBuffer buffer;
  buffer.format = DepthFormat::kInverse16;
  buffer.data = codes.data();
  buffer.stride = static_cast<size_t>(info.face_width) * sizeof(uint16_t);
  buffer.size = codes.size() * sizeof(uint16_t);
  SVC_RETURN_IF_ERROR(reader.decode_face_depth_into(cell, face, buffer));
  std::vector<uint8_t> bytes;
  bytes.reserve(codes.size() * 2);
  for (uint16_t code : codes) {
    bytes.push_back(static_cast<uint8_t>(code));
    bytes.push_back(static_cast<uint8_t>(code >> 8));
  }
  md5.update(bytes);
  return Status();
}

}  // namespace

Result<std::string> stream_md5(const std::filesystem::path& stream, const DecodeSettings& settings) {
  ReaderSettings reader_settings = default_reader_settings();
  reader_settings.decode_threads = settings.threads;
  reader_settings.prefetch_threads = settings.prefetch ? 2 : 0;
  if (!settings.face_caches) reader_settings.face_cache_bytes = reader_settings.reference_cache_bytes = 0;
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(stream, reader_settings));
  Md5 md5;
  for (const CellEntry& cell : reader->cells()) {
    if (settings.prefetch) SVC_RETURN_IF_ERROR(reader->set_viewer(cell.index));
    for (Face face : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(std::shared_ptr<const ImageYCbCr420> image,
                           reader->acquire_face_ycbcr(cell.index, face));
      md5.update(image->y);
      md5.update(image->cb);
      md5.update(image->cr);
    }
  }
  if (reader->info().has_depth) {
    for (const CellEntry& cell : reader->cells()) {
      for (Face face : kAllFaces) SVC_RETURN_IF_ERROR(hash_depth(*reader, cell.index, face, md5));
    }
  }
  return md5.hex_digest();
}

}  // namespace svc::conformance
