// SPDX-License-Identifier: BSD-2-Clause
// Output files that appear at their final path only when complete.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>

#include "svc/status.h"

namespace svc {

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
