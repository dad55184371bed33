// Helpers shared by the test programs.
#pragma once

#include <filesystem>
#include <string>

namespace svc::testing {

// A fresh, empty directory under the system temp folder, removed on destruction.
class TempDir {
 public:
  explicit TempDir(const std::string& tag = "svc-test");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace svc::testing
