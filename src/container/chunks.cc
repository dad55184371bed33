// SPDX-License-Identifier: BSD-2-Clause
// Chunk framing, the file header and commit slots, and opening a container at its newest
// valid commit (docs/format.md).
#include <algorithm>
#include <string>

#include "common/bytes.h"
#include "container/container.h"

namespace svc {

namespace {

constexpr uint8_t kMagic[8] = {0x89, 'S', 'V', 'C', 0x0D, 0x0A, 0x1A, 0x0A};

}  // namespace

Status corrupt_at(const std::string& what, uint64_t offset) {
  return Status(ErrorCode::kCorruptData, what + " at byte offset " + std::to_string(offset));
}

std::vector<uint8_t> make_chunk(uint32_t tag, std::span<const uint8_t> payload) {
  ByteWriter w;
  w.u32(tag);
  w.u64(payload.size());
  w.raw(payload);
  w.u32(crc32_of(w.bytes()));
  return w.take();
}

std::vector<uint8_t> make_bare_chunk(std::span<const uint8_t> payload) {
  ByteWriter w;
  w.raw(payload);
  w.u32(crc32_of(payload));
  return w.take();
}

std::vector<uint8_t> make_file_header() {
  ByteWriter w;
  w.raw(kMagic);
  w.u16(kFormatMajor);
  w.u16(kFormatMinor);
  w.u32(static_cast<uint32_t>(kPreludeSize));
  w.u32(0);  // flags
  w.u32(0);  // reserved
  w.u32(0);  // reserved
  w.u32(crc32_of(w.bytes()));
  return w.take();
}

std::vector<uint8_t> make_commit_slot(uint64_t generation, uint64_t index_offset, uint64_t index_chunk_size) {
  ByteWriter w;
  w.u64(generation);
  w.u64(index_offset);
  w.u64(index_chunk_size);
  w.u32(0);  // reserved
  w.u32(crc32_of(w.bytes()));
  return w.take();
}

namespace {

struct CommitSlot {
  bool valid = false;
  bool empty = false;
  uint64_t generation = 0, index_offset = 0, index_chunk_size = 0;
};

CommitSlot parse_slot(std::span<const uint8_t> bytes) {
  CommitSlot slot;
  ByteReader r(bytes);
  slot.generation = r.u64();
  slot.index_offset = r.u64();
  slot.index_chunk_size = r.u64();
  r.u32();
  const uint32_t crc = r.u32();
  slot.valid = r.ok() && slot.generation != 0 && crc == crc32_of(bytes.first(kCommitSlotSize - 4));
  slot.empty = std::all_of(bytes.begin(), bytes.end(), [](uint8_t b) { return b == 0; });
  return slot;
}

// The chunk of `size` bytes at `offset`, framing included, if it lies inside the file.
Result<std::vector<uint8_t>> read_chunk_bytes(const ReadOnlyFile& file, uint64_t offset, uint64_t size,
                                              const std::string& what) {
  if (offset > file.size() || size > file.size() - offset) {
    return corrupt_at(what + " chunk of " + std::to_string(size) + " bytes lies outside the file", offset);
  }
  Result<std::vector<uint8_t>> bytes = file.read_vector(offset, size);
  if (!bytes.ok()) return bytes.status().with_context("cannot read the " + what + " chunk");
  return bytes;
}

// Every chunk, bare or framed, ends with the CRC-32 of the bytes before it.
Status check_trailing_crc(std::span<const uint8_t> chunk, uint64_t offset, const std::string& what) {
  ByteReader r(chunk.last(4), offset + chunk.size() - 4);
  if (r.u32() != crc32_of(chunk.first(chunk.size() - 4))) {
    return corrupt_at(what + " chunk fails its CRC-32 check (" + std::to_string(chunk.size()) + " bytes)", offset);
  }
  return Status::Ok();
}

}  // namespace

Result<std::vector<uint8_t>> read_chunk(const ReadOnlyFile& file, uint64_t offset, uint64_t chunk_size,
                                        uint32_t expected_tag, const std::string& what) {
  if (chunk_size < kChunkOverhead) {
    return corrupt_at(what + " chunk of " + std::to_string(chunk_size) + " bytes lies outside the file", offset);
  }
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, read_chunk_bytes(file, offset, chunk_size, what));
  ByteReader r(bytes, offset);
  const uint32_t tag = r.u32();
  const uint64_t payload_size = r.u64();
  if (tag != expected_tag) return corrupt_at(what + " chunk has a wrong tag", offset);
  if (payload_size != chunk_size - kChunkOverhead) {
    return corrupt_at(what + " chunk's size field does not match the index", offset + 4);
  }
  SVC_RETURN_IF_ERROR(check_trailing_crc(bytes, offset, what));
  bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(chunk_size - 4), bytes.end());
  bytes.erase(bytes.begin(), bytes.begin() + 12);
  return bytes;
}

Result<OpenedContainer> open_container(const ReadOnlyFile& file, const ReaderLimits& limits) {
  const std::string name = file.name();
  if (file.size() < kPreludeSize) {
    return Status(ErrorCode::kCorruptData,
                  name + " is too short to be an .svc file (" + std::to_string(file.size()) + " bytes)");
  }
  std::vector<uint8_t> prelude(kPreludeSize);
  SVC_RETURN_IF_ERROR(file.read_at(0, prelude));
  if (!std::equal(std::begin(kMagic), std::end(kMagic), prelude.begin())) {
    return Status(ErrorCode::kCorruptData, name + " is not an .svc file (bad signature)");
  }
  ByteReader header(std::span<const uint8_t>(prelude).first(kFileHeaderSize));
  header.skip(8);
  const uint16_t major = header.u16();
  const uint16_t minor = header.u16();
  const uint32_t prelude_size = header.u32();
  header.skip(12);
  const uint32_t header_crc = header.u32();
  if (header_crc != crc32_of(std::span<const uint8_t>(prelude).first(kFileHeaderSize - 4))) {
    return Status(ErrorCode::kCorruptData, name + ": file header fails its CRC-32 check at byte offset 0");
  }
  if (major != kFormatMajor) {
    return Status(ErrorCode::kUnsupported, name + ": format version " + std::to_string(major) + "." +
                                               std::to_string(minor) + " is not supported");
  }
  if (prelude_size != kPreludeSize) {
    return Status(ErrorCode::kCorruptData, name + ": header size field is wrong at byte offset 12");
  }

  const std::span<const uint8_t> slots(prelude.data() + kFileHeaderSize, 2 * kCommitSlotSize);
  CommitSlot slot[2] = {parse_slot(slots.first(kCommitSlotSize)), parse_slot(slots.last(kCommitSlotSize))};
  // Try the newest valid slot first; fall back to the other (an interrupted commit).
  int order[2] = {0, 1};
  if (slot[1].valid && (!slot[0].valid || slot[1].generation > slot[0].generation)) std::swap(order[0], order[1]);
  Status first_error;
  for (int k : order) {
    if (!slot[k].valid) continue;
    const CommitSlot& s = slot[k];
    if (s.index_chunk_size > limits.max_index_bytes + kChunkOverhead) {
      first_error =
          Status(ErrorCode::kLimitExceeded, name + ": index of " + std::to_string(s.index_chunk_size) +
                                                " bytes is above the reader's limit (its size in commit slot " +
                                                std::to_string(k) + ", at byte offset " +
                                                std::to_string(kFileHeaderSize + k * kCommitSlotSize + 16) + ")");
      continue;
    }
    auto payload = read_chunk(file, s.index_offset, s.index_chunk_size, kIndexChunkTag, "index");
    if (!payload.ok()) {
      if (first_error.ok()) first_error = payload.status().with_context(name);
      continue;
    }
    auto index = parse_index(*payload, s.index_offset + 12, file.size(), limits);
    if (!index.ok()) {
      if (first_error.ok()) first_error = index.status().with_context(name + ": index");
      continue;
    }
    OpenedContainer opened;
    opened.index = std::move(index).value();
    opened.index_offset = s.index_offset;
    opened.index_chunk_size = s.index_chunk_size;
    opened.generation = s.generation;
    opened.slot = k;
    opened.fell_back = k != order[0] && slot[order[0]].valid;
    for (int j = 0; j < 2; ++j) opened.slot_damaged[j] = !slot[j].valid && !slot[j].empty;
    return opened;
  }
  if (!first_error.ok()) return first_error;
  return Status(ErrorCode::kCorruptData, name + ": no valid commit slot (bytes 32-95): the file holds no index");
}

Result<std::vector<uint8_t>> read_frame_payload(const ReadOnlyFile& file, const FrameRecord& frame,
                                                const std::string& what) {
  if (!frame.bare_chunk) {
    return read_chunk(file, frame.chunk_offset, color_chunk_bytes(frame), kFaceChunkTag, what);
  }
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes,
                       read_chunk_bytes(file, frame.chunk_offset, color_chunk_bytes(frame), what));
  SVC_RETURN_IF_ERROR(check_trailing_crc(bytes, frame.chunk_offset, what));
  bytes.resize(frame.payload_size);
  return bytes;
}

Result<std::vector<uint8_t>> read_frame_depth(const ReadOnlyFile& file, const FrameRecord& frame,
                                              const std::string& what) {
  if (frame.depth_size == 0) return Status(ErrorCode::kNotFound, what + " has no depth");
  const uint64_t offset = frame.chunk_offset + color_chunk_bytes(frame);
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, read_chunk_bytes(file, offset, depth_chunk_bytes(frame), what));
  SVC_RETURN_IF_ERROR(check_trailing_crc(bytes, offset, what + " depth"));
  bytes.resize(frame.depth_size);
  return bytes;
}

}  // namespace svc
