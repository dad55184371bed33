// SPDX-License-Identifier: BSD-2-Clause
#include "output/writer.h"

namespace svc {

Result<std::unique_ptr<ContainerWriter>> ContainerWriter::create(const std::filesystem::path& path) {
  SVC_ASSIGN_OR_RETURN(auto out, AtomicOutputFile::create(path));
  const std::vector<uint8_t> header = make_file_header();
  SVC_RETURN_IF_ERROR(out->write(header));
  const std::vector<uint8_t> empty_slots(2 * kCommitSlotSize, 0);
  SVC_RETURN_IF_ERROR(out->write(empty_slots));
  return std::unique_ptr<ContainerWriter>(new ContainerWriter(std::move(out)));
}

Result<uint64_t> ContainerWriter::append_frame(std::span<const uint8_t> payload) {
  const uint64_t offset = out_->position();
  SVC_RETURN_IF_ERROR(out_->write(make_bare_chunk(payload)));
  return offset;
}

Status ContainerWriter::finish(std::span<const uint8_t> index_payload) {
  const uint64_t index_offset = out_->position();
  const std::vector<uint8_t> chunk = make_chunk(kIndexChunkTag, index_payload);
  SVC_RETURN_IF_ERROR(out_->write(chunk));
  SVC_RETURN_IF_ERROR(out_->write_at(kFileHeaderSize, make_commit_slot(1, index_offset, chunk.size())));
  return out_->commit();
}

}  // namespace svc
