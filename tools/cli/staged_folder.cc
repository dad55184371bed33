#include "cli/staged_folder.h"

#include <string>

#include <unistd.h>

namespace svc::cli {

namespace fs = std::filesystem;

namespace {

Status io_error(const std::string& what, const fs::path& path, const std::error_code& ec) {
  return Status(ErrorCode::kIoError, "cannot " + what + " " + path.string() + ": " + ec.message());
}

// Moves every file under `from` to the same place under `to`, replacing files there.
Status move_tree(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(from, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const fs::path target = to / fs::relative(it->path(), from);
    if (it->is_directory()) {
      fs::create_directories(target, ec);
      if (ec) return io_error("create", target, ec);
    } else {
      fs::rename(it->path(), target, ec);
      if (ec) return io_error("write", target, ec);
    }
  }
  if (ec) return io_error("read", from, ec);
  return Status::Ok();
}

}  // namespace

StagedFolder::StagedFolder(fs::path destination, fs::path staging)
    : destination_(std::move(destination)), staging_(std::move(staging)) {}

Result<std::unique_ptr<StagedFolder>> StagedFolder::create(const fs::path& destination) {
  fs::path target = destination.lexically_normal();
  if (target.filename().empty()) target = target.parent_path();  // "out/"
  const fs::path staging =
      target.parent_path() / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()));
  std::error_code ec;
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
  SVC_RETURN_IF_ERROR(move_tree(staging_, destination_));
  fs::remove_all(staging_, ec);
  committed_ = true;
  return Status::Ok();
}

}  // namespace svc::cli
