// SPDX-License-Identifier: BSD-2-Clause
// An output folder written beside its destination and moved into place only when
// complete, so that a failed or interrupted command leaves nothing behind. Not
// thread-safe; one owner.
#pragma once

#include <filesystem>
#include <memory>

#include "svc/status.h"

namespace svc::command_line {

class StagedFolder {
 public:
  // Creates the staging folder ".NAME.tmp-PID" beside `destination`. Errors: kIoError.
  static Result<std::unique_ptr<StagedFolder>> create(const std::filesystem::path& destination);
  // Removes the staging folder unless commit() succeeded.
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  // Where to write.
  const std::filesystem::path& path() const { return staging_; }

  // Moves what was written to the destination: renamed into place when the destination
  // is missing or an empty folder; otherwise each entry written (manifest.json, cells/)
  // replaces the same-named entry there whole, so old and new images never mix, and
  // entries the command does not write stay (the caller has checked that the destination
  // may be replaced, see check_output). On failure the destination is as it was.
  // Errors: kIoError naming the path.
  Status commit();

 private:
  StagedFolder(std::filesystem::path destination, std::filesystem::path staging);
  Status replace_entries();
  std::filesystem::path destination_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace svc::command_line
