// SPDX-License-Identifier: BSD-2-Clause
// File access for the container: checked positioned reads of a byte source.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "svc/byte_source.h"
#include "svc/status.h"

namespace svc {

// A ByteSource as the container reads it: every read checked against the source's size
// (kCorruptData past the end, naming the source and offset) and the source's errors
// named. read_at is thread-safe.
class ReadOnlyFile {
 public:
  explicit ReadOnlyFile(std::unique_ptr<ByteSource> source);
  // The file at `path` (open_file_source).
  static Result<std::unique_ptr<ReadOnlyFile>> open(const std::filesystem::path& path);
  ReadOnlyFile(const ReadOnlyFile&) = delete;
  ReadOnlyFile& operator=(const ReadOnlyFile&) = delete;

  uint64_t size() const { return size_; }
  // The source's name, for messages: the path of a file.
  const std::string& name() const { return source_->name(); }
  // Reads exactly out.size() bytes at `offset`; kCorruptData if the source is shorter.
  Status read_at(uint64_t offset, std::span<uint8_t> out) const;
  Result<std::vector<uint8_t>> read_vector(uint64_t offset, uint64_t size) const;

 private:
  std::unique_ptr<ByteSource> source_;
  uint64_t size_;
};

}  // namespace svc
