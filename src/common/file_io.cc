// SPDX-License-Identifier: BSD-2-Clause
#include "common/file_io.h"

#include <string>

namespace svc {

ReadOnlyFile::ReadOnlyFile(std::unique_ptr<ByteSource> source)
    : source_(std::move(source)), size_(source_->size()) {}

Result<std::unique_ptr<ReadOnlyFile>> ReadOnlyFile::open(const std::filesystem::path& path) {
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<ByteSource> source, open_file_source(path));
  return std::make_unique<ReadOnlyFile>(std::move(source));
}

Status ReadOnlyFile::read_at(uint64_t offset, std::span<uint8_t> out) const {
  if (offset > size_ || out.size() > size_ - offset) {
    return Status(ErrorCode::kCorruptData, name() + ": read of " + std::to_string(out.size()) +
                                               " bytes at offset " + std::to_string(offset) +
                                               " runs past the end of the file (" + std::to_string(size_) +
                                               " bytes)");
  }
  if (out.empty()) return Status::Ok();
  const Status read = source_->read_at(offset, out);
  if (read.ok()) return read;
  return read.with_context(name() + ": read of " + std::to_string(out.size()) + " bytes at offset " +
                           std::to_string(offset));
}

Result<std::vector<uint8_t>> ReadOnlyFile::read_vector(uint64_t offset, uint64_t size) const {
  if (offset > size_ || size > size_ - offset) {
    return Status(ErrorCode::kCorruptData, name() + ": " + std::to_string(size) + " bytes at offset " +
                                               std::to_string(offset) + " lie past the end of the file (" +
                                               std::to_string(size_) + " bytes)");
  }
  std::vector<uint8_t> data(static_cast<size_t>(size));
  SVC_RETURN_IF_ERROR(read_at(offset, data));
  return data;
}

}  // namespace svc
