// An output folder written beside its destination and moved into place only when
// complete, so that a failed or interrupted command leaves nothing behind.
#pragma once

#include <filesystem>
#include <memory>

#include "svc/status.h"

namespace svc::cli {

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
  // is missing or an empty folder, else file by file over what is there (the caller has
  // checked that the destination may be written, see check_output).
  Status commit();

 private:
  StagedFolder(std::filesystem::path destination, std::filesystem::path staging);
  std::filesystem::path destination_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace svc::cli
