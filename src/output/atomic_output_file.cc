// SPDX-License-Identifier: BSD-2-Clause
#include "output/atomic_output_file.h"

#include <cerrno>
#include <cstring>
#include <random>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace svc {

namespace {

std::string errno_text() { return std::strerror(errno); }

}  // namespace

Result<std::unique_ptr<AtomicOutputFile>> AtomicOutputFile::create(const std::filesystem::path& final_path) {
  std::filesystem::path dir = final_path.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    return Status(ErrorCode::kIoError,
                  "cannot write " + final_path.string() + ": folder " + dir.string() + " does not exist");
  }
  if (std::filesystem::is_directory(final_path, ec)) {
    return Status(ErrorCode::kIoError, "cannot write " + final_path.string() + ": it is a folder");
  }
  std::random_device rd;
  for (int attempt = 0; attempt < 16; ++attempt) {
    auto temp = final_path;
    temp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(rd() % 1000000);
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd >= 0) return std::unique_ptr<AtomicOutputFile>(new AtomicOutputFile(fd, temp, final_path));
    if (errno != EEXIST) {
      return Status(ErrorCode::kIoError, "cannot write " + final_path.string() + ": " + errno_text());
    }
  }
  return Status(ErrorCode::kIoError, "cannot create a temporary file beside " + final_path.string());
}

AtomicOutputFile::~AtomicOutputFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) ::unlink(temp_path_.c_str());
}

Status AtomicOutputFile::write_at(uint64_t offset, std::span<const uint8_t> data) {
  size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::pwrite(fd_, data.data() + done, data.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      return Status(ErrorCode::kIoError, "write to " + temp_path_.string() + " failed: " + errno_text());
    }
    done += static_cast<size_t>(n);
  }
  return Status::Ok();
}

Status AtomicOutputFile::write(std::span<const uint8_t> data) {
  SVC_RETURN_IF_ERROR(write_at(position_, data));
  position_ += data.size();
  return Status::Ok();
}

Status AtomicOutputFile::commit() {
  if (::fsync(fd_) != 0) {
    return Status(ErrorCode::kIoError, "sync of " + temp_path_.string() + " failed: " + errno_text());
  }
  ::close(fd_);
  fd_ = -1;
  if (::rename(temp_path_.c_str(), final_path_.c_str()) != 0) {
    return Status(ErrorCode::kIoError,
                  "cannot rename " + temp_path_.string() + " to " + final_path_.string() + ": " + errno_text());
  }
  committed_ = true;
  // Make the rename itself durable.
  std::filesystem::path dir = final_path_.parent_path();
  if (dir.empty()) dir = ".";
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
  return Status::Ok();
}

}  // namespace svc
