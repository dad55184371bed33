// SPDX-License-Identifier: BSD-2-Clause
// Helpers shared by the test programs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

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
std::vector<uint8_t> read_file_data(const std::filesystem::path& path);

// Fails the running test for every regular file of `first` that is missing from `second`
// or differs in a byte; returns the number of files compared.
int expect_identical_trees(const std::filesystem::path& first, const std::filesystem::path& second);

// A program of the build (build/bin/PROGRAM) as a user runs it from a shell.
struct CliRun {
  int exit_code = -1;  // -1 when it did not exit normally
  std::string output;  // stdout and stderr together
};

// 'path' with single quotes, for a shell command line.
std::string quoted(const std::filesystem::path& path);

// Runs build/bin/PROGRAM ARGS (ARGS as a shell sees them) in `dir`.
CliRun run_program(const std::string& program, const std::string& args, const std::filesystem::path& dir);

}  // namespace svc::testing
