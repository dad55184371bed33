// SPDX-License-Identifier: BSD-2-Clause
// Writing a new .svc file in one pass (docs/format.md).
#pragma once

#include <filesystem>
#include <memory>
#include <span>

#include "common/file_io.h"
#include "container/container.h"
#include "output/atomic_output_file.h"

namespace svc {

// Writes a new container: header and slots, then face chunks, then the index.
class ContainerWriter {
 public:
  static Result<std::unique_ptr<ContainerWriter>> create(const std::filesystem::path& path);
  // Appends a FACE chunk; returns its file offset.
  Result<uint64_t> append_frame(std::span<const uint8_t> payload);
  // The file as written so far, for reading chunks back (read_frame_payload).
  Result<std::unique_ptr<ReadOnlyFile>> open_written() const { return ReadOnlyFile::open(out_->temp_path()); }
  // Writes the index, commits slot 0 and renames the file into place.
  Status finish(const ContainerIndex& index) { return finish(serialize_index(index)); }
  // The same with the index already serialized (serialize_index).
  Status finish(std::span<const uint8_t> index_payload);

 private:
  explicit ContainerWriter(std::unique_ptr<AtomicOutputFile> out) : out_(std::move(out)) {}
  std::unique_ptr<AtomicOutputFile> out_;
};

}  // namespace svc
