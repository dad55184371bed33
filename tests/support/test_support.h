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

// The whole file as bytes; empty when it cannot be read.
std::string read_file_bytes(const std::filesystem::path& path);

// Fails the running test for every regular file of `first` that is missing from `second`
// or differs in a byte; returns the number of files compared.
int expect_identical_trees(const std::filesystem::path& first, const std::filesystem::path& second);

}  // namespace svc::testing
