// File access for the container: checked positioned reads of a byte source, and output
// files that appear at their final path only when complete.
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

// Writes to a temporary file beside `final_path`; commit() flushes, syncs and renames
// it into place. Destroyed without commit(), it removes the temporary file, so a
// failed or interrupted write never leaves a partial file at `final_path`.
class AtomicOutputFile {
 public:
  static Result<std::unique_ptr<AtomicOutputFile>> create(const std::filesystem::path& final_path);
  ~AtomicOutputFile();
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

  Status write(std::span<const uint8_t> data);
  Status write_at(uint64_t offset, std::span<const uint8_t> data);
  uint64_t position() const { return position_; }
  // The temporary file being written, for reading back what is written so far.
  const std::filesystem::path& temp_path() const { return temp_path_; }
  Status commit();

 private:
  AtomicOutputFile(int fd, std::filesystem::path temp, std::filesystem::path final_path)
      : fd_(fd), temp_path_(std::move(temp)), final_path_(std::move(final_path)) {}
  int fd_;
  std::filesystem::path temp_path_;
  std::filesystem::path final_path_;
  uint64_t position_ = 0;
  bool committed_ = false;
};

}  // namespace svc
