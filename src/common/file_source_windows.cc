// SPDX-License-Identifier: BSD-2-Clause
// open_file_source on Windows: ReadFile at an offset given in an OVERLAPPED, which leaves
// the handle's file pointer alone, so reads from several threads need no lock.
#include <windows.h>

#include <algorithm>
#include <string>

#include "svc/byte_source.h"

namespace svc {

namespace {

// Paths in messages as UTF-8, whatever the code page: the wide path always converts.
std::string display_name(const std::filesystem::path& path) {
  const std::u8string name = path.u8string();
  return std::string(name.begin(), name.end());
}

std::string error_text(DWORD error) {
  char* text = nullptr;
  const DWORD size =
      FormatMessageA(FORMAT_MESSAGE_ALLOCATE_BUFFER | FORMAT_MESSAGE_FROM_SYSTEM | FORMAT_MESSAGE_IGNORE_INSERTS,
                     nullptr, error, 0, reinterpret_cast<char*>(&text), 0, nullptr);
  std::string message = size > 0 ? std::string(text, size) : "Windows error " + std::to_string(error);
  LocalFree(text);
  while (!message.empty() && (message.back() == '\n' || message.back() == '\r' || message.back() == '.')) {
    message.pop_back();
  }
  return message;
}

class WindowsFileSource final : public ByteSource {
 public:
  WindowsFileSource(HANDLE file, uint64_t size, std::string name)
      : file_(file), size_(size), name_(std::move(name)) {}
  ~WindowsFileSource() override { CloseHandle(file_); }
  uint64_t size() const override { return size_; }
  const std::string& name() const override { return name_; }

  Status read_at(uint64_t offset, std::span<uint8_t> out) const override {
    size_t done = 0;
    while (done < out.size()) {
      // ReadFile takes a 32-bit count.
      const DWORD want = static_cast<DWORD>(std::min<size_t>(out.size() - done, 1u << 30));
      OVERLAPPED at{};
      at.Offset = static_cast<DWORD>(offset + done);
      at.OffsetHigh = static_cast<DWORD>((offset + done) >> 32);
      DWORD got = 0;
      if (!ReadFile(file_, out.data() + done, want, &got, &at)) {
        const DWORD error = GetLastError();
        if (error != ERROR_HANDLE_EOF) return Status(ErrorCode::kIoError, error_text(error));
      }
      if (got == 0) {
        return Status(ErrorCode::kIoError, "unexpected end of file at offset " + std::to_string(offset + done));
      }
      done += got;
    }
    return Status::Ok();
  }

 private:
  HANDLE file_;
  uint64_t size_;
  std::string name_;
};

ErrorCode open_error_code(DWORD error) {
  return error == ERROR_FILE_NOT_FOUND || error == ERROR_PATH_NOT_FOUND ? ErrorCode::kNotFound
                                                                        : ErrorCode::kIoError;
}

}  // namespace

Result<std::unique_ptr<ByteSource>> open_file_source(const std::filesystem::path& path) {
  const std::string name = display_name(path);
  // Others may read, replace or delete the file meanwhile, as on POSIX systems.
  const HANDLE file = CreateFileW(path.c_str(), GENERIC_READ,
                                  FILE_SHARE_READ | FILE_SHARE_WRITE | FILE_SHARE_DELETE, nullptr, OPEN_EXISTING,
                                  FILE_ATTRIBUTE_NORMAL, nullptr);
  if (file == INVALID_HANDLE_VALUE) {
    const DWORD error = GetLastError();
    return Status(open_error_code(error), "cannot open " + name + ": " + error_text(error));
  }
  LARGE_INTEGER size{};
  if (GetFileType(file) != FILE_TYPE_DISK || !GetFileSizeEx(file, &size)) {
    CloseHandle(file);
    return Status(ErrorCode::kIoError, name + " is not a regular file");
  }
  return std::unique_ptr<ByteSource>(new WindowsFileSource(file, static_cast<uint64_t>(size.QuadPart), name));
}

}  // namespace svc
