// SPDX-License-Identifier: BSD-2-Clause
#include "output/updater.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace svc {

namespace {

std::atomic<int64_t> g_kill_after_bytes{-1};

}  // namespace

void set_updater_kill_after_bytes_for_testing(int64_t bytes) { g_kill_after_bytes.store(bytes); }

Result<std::unique_ptr<ContainerUpdater>> ContainerUpdater::open(const std::filesystem::path& path,
                                                                 const ReaderLimits& limits) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) {
    const ErrorCode code = errno == ENOENT ? ErrorCode::kNotFound : ErrorCode::kIoError;
    return Status(code, "cannot open " + path.string() + " for update: " + std::strerror(errno));
  }
  auto fail = [&](Status status) {
    ::close(fd);
    return status;
  };
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    return fail(Status(ErrorCode::kIoError, path.string() + " is being updated by another process"));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    return fail(Status(ErrorCode::kIoError, path.string() + " is not a regular file"));
  }
  // Opened after the lock, so no other updater is mid-commit while the index is read.
  auto file = ReadOnlyFile::open(path);
  if (!file.ok()) return fail(file.status());
  auto opened = open_container(**file, limits);
  if (!opened.ok()) return fail(opened.status());
  if (opened->fell_back) {
    return fail(Status(ErrorCode::kCorruptData,
                       path.string() + ": the newest index is damaged (an older one is in use); run svc verify"));
  }
  // Committed data ends with the last chunk the index refers to; anything after it was
  // appended by an update that never committed.
  uint64_t end = opened->index_offset + opened->index_chunk_size;
  for (const FrameRecord& frame : opened->index.frames) {
    end = std::max(end, frame.chunk_offset + chunk_bytes(frame));
  }
  if (end < (*file)->size() && ::ftruncate(fd, static_cast<off_t>(end)) != 0) {
    return fail(Status(ErrorCode::kIoError,
                       "cannot cut uncommitted bytes off " + path.string() + ": " + std::strerror(errno)));
  }
  return std::unique_ptr<ContainerUpdater>(
      new ContainerUpdater(fd, std::move(file).value(), std::move(opened).value(), end));
}

ContainerUpdater::~ContainerUpdater() {
  // Uncommitted chunks are unreferenced; cut them off again (best effort).
  if (!committed_once_ && end_ > start_) (void)::ftruncate(fd_, static_cast<off_t>(start_));
  ::close(fd_);  // also releases the lock
}

Status ContainerUpdater::write_at(uint64_t offset, std::span<const uint8_t> data) {
  int64_t budget = g_kill_after_bytes.load();
  if (budget >= 0) {
    if (static_cast<uint64_t>(budget) < data.size()) {
      // A crash in the middle of this write: what reached the file stays, then death.
      (void)::pwrite(fd_, data.data(), static_cast<size_t>(budget), static_cast<off_t>(offset));
      ::raise(SIGKILL);
    }
    g_kill_after_bytes.store(budget - static_cast<int64_t>(data.size()));
  }
  size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::pwrite(fd_, data.data() + done, data.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      return Status(ErrorCode::kIoError, "write to " + file_->name() + " at byte offset " +
                                             std::to_string(offset + done) + " failed: " + std::strerror(errno));
    }
    done += static_cast<size_t>(n);
  }
  return Status::Ok();
}

Status ContainerUpdater::sync(const char* what) {
  if (::fsync(fd_) != 0) {
    return Status(ErrorCode::kIoError,
                  "sync of " + file_->name() + " " + what + " failed: " + std::strerror(errno));
  }
  return Status::Ok();
}

Result<uint64_t> ContainerUpdater::append_frame(std::span<const uint8_t> payload) {
  if (committed_once_) return Status(ErrorCode::kInternal, "append after commit");
  const uint64_t offset = end_;
  const std::vector<uint8_t> chunk = make_bare_chunk(payload);
  SVC_RETURN_IF_ERROR(write_at(offset, chunk));
  end_ += chunk.size();
  return offset;
}

Status ContainerUpdater::commit(const ContainerIndex& index) {
  if (committed_once_) return Status(ErrorCode::kInternal, "commit called twice");
  const uint64_t index_offset = end_;
  const std::vector<uint8_t> chunk = make_chunk(kIndexChunkTag, serialize_index(index));
  SVC_RETURN_IF_ERROR(write_at(index_offset, chunk));
  end_ += chunk.size();
  // The index and every face chunk must be durable before a slot points at them.
  SVC_RETURN_IF_ERROR(sync("before the commit"));
  const int slot = 1 - committed_.slot;
  const std::vector<uint8_t> record = make_commit_slot(committed_.generation + 1, index_offset, chunk.size());
  SVC_RETURN_IF_ERROR(write_at(kFileHeaderSize + static_cast<uint64_t>(slot) * kCommitSlotSize, record));
  SVC_RETURN_IF_ERROR(sync("after the commit"));
  committed_once_ = true;
  return Status::Ok();
}

}  // namespace svc
