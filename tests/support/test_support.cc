// SPDX-License-Identifier: BSD-2-Clause
#include "support/test_support.h"

#include <atomic>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <system_error>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

namespace svc::testing {

TempDir::TempDir(const std::string& tag) {
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  const auto base = std::filesystem::temp_directory_path();
  for (;;) {
    auto candidate = base / (tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
                             std::to_string(rd() % 100000));
    std::error_code ec;
    if (std::filesystem::create_directory(candidate, ec)) {
      path_ = candidate;
      return;
    }
  }
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::string read_file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<uint8_t> read_file_data(const std::filesystem::path& path) {
  const std::string bytes = read_file_bytes(path);
  return std::vector<uint8_t>(bytes.begin(), bytes.end());
}

int expect_identical_trees(const std::filesystem::path& first, const std::filesystem::path& second) {
  int files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(first)) {
    if (!entry.is_regular_file()) continue;
    const std::filesystem::path rel = std::filesystem::relative(entry.path(), first);
    if (!std::filesystem::exists(second / rel)) {
      ADD_FAILURE() << rel << " is missing from " << second;
    } else if (read_file_bytes(entry.path()) != read_file_bytes(second / rel)) {
      ADD_FAILURE() << rel << " differs";
    }
    ++files;
  }
  return files;
}

std::string quoted(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

CliRun run_program(const std::string& program, const std::string& args, const std::filesystem::path& dir) {
  const std::string command = "cd " + quoted(dir) + " && " +
                              quoted(std::filesystem::path(SVC_BINARY_DIR) / "bin" / program) + " " + args +
                              " 2>&1";
  CliRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) run.output.append(buffer, n);
  const int status = ::pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

}  // namespace svc::testing
