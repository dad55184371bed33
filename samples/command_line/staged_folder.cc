// SPDX-License-Identifier: BSD-2-Clause
#include "command_line/staged_folder.h"

#include <string>
#include <vector>

#include <unistd.h>

namespace svc::command_line {

namespace fs = std::filesystem;

namespace {

Status io_error(const std::string& what, const fs::path& path, const std::error_code& ec) {
  return Status(ErrorCode::kIoError, "cannot " + what + " " + path.string() + ": " + ec.message());
}

// ".NAME.SUFFIX-PID" beside `target`.
fs::path beside(const fs::path& target, const std::string& suffix) {
  return target.parent_path() /
         ("." + target.filename().string() + "." + suffix + "-" + std::to_string(::getpid()));
}

}  // namespace

StagedFolder::StagedFolder(fs::path destination, fs::path staging)
    : destination_(std::move(destination)), staging_(std::move(staging)) {}

Result<std::unique_ptr<StagedFolder>> StagedFolder::create(const fs::path& destination) {
  std::error_code ec;
  // Absolute, so that "." and "out/" have a name and a parent to stage beside.
  fs::path target = fs::absolute(destination, ec).lexically_normal();
  if (target.filename().empty()) target = target.parent_path();  // "out/"
  const fs::path staging = beside(target, "tmp");
  fs::create_directories(staging, ec);
  if (ec) return io_error("create", staging, ec);
  return std::unique_ptr<StagedFolder>(new StagedFolder(target, staging));
}

StagedFolder::~StagedFolder() {
  std::error_code ec;
  if (!committed_) fs::remove_all(staging_, ec);
}

Status StagedFolder::commit() {
  std::error_code ec;
  if (fs::is_directory(destination_, ec) && fs::is_empty(destination_, ec)) fs::remove(destination_, ec);
  if (!fs::exists(destination_, ec)) {
    fs::rename(staging_, destination_, ec);
    if (ec) return io_error("write", destination_, ec);
    committed_ = true;
    return Status::Ok();
  }
  SVC_RETURN_IF_ERROR(replace_entries());
  committed_ = true;
  fs::remove_all(staging_, ec);
  return Status::Ok();
}

// Each entry written (manifest.json, cells/, ...) replaces the same-named entry of the
// destination whole, never merged with it: no old image survives beside the new ones.
// Entries this command does not write (the user's own files) stay. The replaced ones
// are moved aside first and removed at the end, or moved back when a rename fails.
Status StagedFolder::replace_entries() {
  const fs::path aside = beside(destination_, "old");
  std::error_code ec;
  fs::create_directories(aside, ec);
  if (ec) return io_error("create", aside, ec);
  std::vector<fs::path> names, moved_aside;
  for (const auto& entry : fs::directory_iterator(staging_, ec)) names.push_back(entry.path().filename());
  if (ec) return io_error("read", staging_, ec);
  Status status = Status::Ok();
  size_t placed = 0;
  for (const fs::path& name : names) {
    if (fs::symlink_status(destination_ / name, ec).type() != fs::file_type::not_found) {
      fs::rename(destination_ / name, aside / name, ec);
      if (ec) status = io_error("replace", destination_ / name, ec);
      if (ec) break;
      moved_aside.push_back(name);
    }
    fs::rename(staging_ / name, destination_ / name, ec);
    if (ec) status = io_error("write", destination_ / name, ec);
    if (ec) break;
    ++placed;
  }
  if (!status.ok()) {
    std::error_code undo;
    for (size_t i = 0; i < placed; ++i) fs::rename(destination_ / names[i], staging_ / names[i], undo);
    for (const fs::path& name : moved_aside) fs::rename(aside / name, destination_ / name, undo);
  }
  fs::remove_all(aside, ec);
  return status;
}

}  // namespace svc::command_line
