// SPDX-License-Identifier: BSD-2-Clause
// Adding to an .svc file in place, crash-safe (docs/format.md, commit slots).
#pragma once

#include <filesystem>
#include <memory>
#include <span>

#include "common/file_io.h"
#include "container/container.h"

namespace svc {

// Adds to an existing container in place (svc add): appends FACE chunks after the last
// byte the committed index refers to (bytes beyond it, left by an update that never
// committed, are cut off first), then commits a new index the crash-safe way (docs/format.md, commit
// slots): append the INDX chunk, fsync, overwrite the commit slot that does not hold the
// newest generation with generation + 1, fsync. No byte a committed index refers to is
// ever written, so until the slot write lands every reader (and a crash at any point)
// sees exactly the old database. An updater destroyed without commit() cuts the file
// back to where it started. A file whose newest index is damaged (fell_back) is refused
// (kCorruptData): adding to an older index would silently drop the newer one.
//
// Holds an exclusive advisory lock (flock) on the file while alive: a second updater of
// the same file fails with kIoError instead of interleaving commits. Readers need no
// lock. Not thread-safe; one thread drives an updater.
class ContainerUpdater {
 public:
  // Opens `path` read-write, locks it and reads the committed index (validated against
  // `limits`). Errors: the container's, or kIoError naming the path.
  static Result<std::unique_ptr<ContainerUpdater>> open(const std::filesystem::path& path,
                                                        const ReaderLimits& limits = ReaderLimits{});
  ~ContainerUpdater();
  ContainerUpdater(const ContainerUpdater&) = delete;
  ContainerUpdater& operator=(const ContainerUpdater&) = delete;

  // The committed state the update starts from.
  const OpenedContainer& committed() const { return committed_; }
  // The file as it was when opened, for reading existing chunks (read_frame_payload).
  const ReadOnlyFile& file() const { return *file_; }

  // Appends a FACE chunk; returns its file offset. Not visible to readers before commit().
  Result<uint64_t> append_frame(std::span<const uint8_t> payload);
  // Appends `index` and commits it as generation committed().generation + 1. After an
  // error the file may hold appended bytes but still opens as the old database.
  Status commit(const ContainerIndex& index);

 private:
  ContainerUpdater(int fd, std::unique_ptr<ReadOnlyFile> file, OpenedContainer committed, uint64_t end)
      : fd_(fd), file_(std::move(file)), committed_(std::move(committed)), start_(end), end_(end) {}
  Status write_at(uint64_t offset, std::span<const uint8_t> data);
  Status sync(const char* what);

  int fd_;
  std::unique_ptr<ReadOnlyFile> file_;
  OpenedContainer committed_;
  uint64_t start_;  // end of the committed data
  uint64_t end_;    // where the next chunk goes
  bool committed_once_ = false;
};

// Fault injection for crash tests: after this many more bytes written by any
// ContainerUpdater in this process (part of a write counts), the process kills itself
// with SIGKILL, leaving the file as a crash at that point would. Negative disables (the
// default). Only for tests that run the update in a child process.
void set_updater_kill_after_bytes_for_testing(int64_t bytes);

}  // namespace svc
