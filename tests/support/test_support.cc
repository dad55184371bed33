#include "support/test_support.h"

#include <atomic>
#include <fstream>
#include <iterator>
#include <random>
#include <system_error>

#include <gtest/gtest.h>
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

}  // namespace svc::testing
