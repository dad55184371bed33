// SPDX-License-Identifier: BSD-2-Clause
// A shard's part file (docs/format.md, "Shards"): the FACE chunks one shard coded, and a
// PART chunk saying which database, settings, svc version and shard they belong to and
// holding the plan of the whole encode, so that `svc merge` needs nothing but the parts.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "common/file_io.h"
#include "container/container.h"
#include "output/atomic_output_file.h"

namespace svc {

inline constexpr uint32_t kPartChunkTag = chunk_tag('P', 'A', 'R', 'T');
inline constexpr uint64_t kPartHeaderSize = 8;    // "SVCPART" and a format version byte
inline constexpr uint64_t kPartTrailerSize = 16;  // PART chunk offset, "SVCPEND" and the version

// Where one coded face lies in the part file.
struct PartFace {
  uint32_t frame = 0;  // ordinal into the plan's frames
  uint64_t chunk_offset = 0;
  uint32_t payload_size = 0;
  uint32_t depth_size = 0;                  // the depth chunk right after the face's (plans with depth)
  uint8_t border_edges = kEveryBorderEdge;  // FrameRecord::border_edges of the coded face
};

struct PartDescriptor {
  std::string svc_version;   // of the program that wrote the part
  uint64_t fingerprint = 0;  // of the database (manifest bytes, sizes of the files it names)
  uint32_t shard = 0;        // 1..shard_count
  uint32_t shard_count = 0;
  // The encoder settings the plan does not hold (shard_settings_text): "" for defaults.
  std::string settings;
  std::vector<PartFace> faces;  // in the order they lie in the file
  // The whole encode's index: cells, cameras, coding, every frame's type and
  // references. Chunk offsets are left unset (0); stats are this part's faces' alone.
  ContainerIndex plan;
};

// Writes a part file: header, then FACE chunks, then the PART chunk and the trailer.
// The file appears at its path only when finish() succeeds (AtomicOutputFile).
class PartWriter {
 public:
  static Result<std::unique_ptr<PartWriter>> create(const std::filesystem::path& path);
  // Appends a FACE chunk; returns its file offset.
  Result<uint64_t> append_frame(std::span<const uint8_t> payload);
  // The file as written so far, for reading chunks back.
  Result<std::unique_ptr<ReadOnlyFile>> open_written() const { return ReadOnlyFile::open(out_->temp_path()); }
  Status finish(const PartDescriptor& descriptor);

 private:
  explicit PartWriter(std::unique_ptr<AtomicOutputFile> out) : out_(std::move(out)) {}
  std::unique_ptr<AtomicOutputFile> out_;
};

struct OpenedPart {
  std::unique_ptr<ReadOnlyFile> file;
  PartDescriptor descriptor;
};

// Opens a part file and reads its descriptor: header, trailer, PART chunk (CRC-checked),
// the plan (validated against `limits`) and the face table (every chunk inside the face
// area, every frame inside the plan). Errors name the file and the byte offset. Faces'
// own chunks are checked when read (read_frame_payload).
Result<OpenedPart> open_part(const std::filesystem::path& path, const ReaderLimits& limits = ReaderLimits{});

}  // namespace svc
