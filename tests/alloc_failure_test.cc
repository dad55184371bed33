// SPDX-License-Identifier: BSD-2-Clause
// Allocation failures injected into the reader (a program of its own: it replaces
// operator new, tests/fuzz/failing_allocator_new.h). For container seeds and, when
// present, the conformance streams, every allocation an open and full decode makes is
// failed in turn (or a stride of them), once and from there on: each call returns an
// error or the clean result, the same reader then decodes exactly as a clean run, and
// nothing is left allocated (the run on a thread of its own, whose per-thread decoder
// buffers go when it ends). The libFuzzer target svc_alloc_failure_fuzzer runs the same
// check (tests/fuzz/reader_entry.h) on arbitrary files.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "fuzz/failing_allocator_new.h"
#include "fuzz/reader_entry.h"
#include "support/test_support.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> test_files() {
  const fs::path source(SVC_SOURCE_DIR);
  std::vector<fs::path> files;
  for (const char* name : {"seed-3x1x1-ib-log.svc", "seed-2x1x2-ib-depth.svc", "seed-3x1x1-ib-stored-depth.svc",
                           "index-v4-3x1x1-ib-log.svc"}) {
    files.push_back(source / "tests/fuzz/corpus/container" / name);
  }
  const fs::path streams = source / "tests/conformance/streams";
  if (fs::is_directory(streams)) {
    std::vector<fs::path> found;
    for (const auto& entry : fs::directory_iterator(streams)) {
      if (entry.path().extension() == ".svc" && entry.file_size() <= (64u << 10)) found.push_back(entry.path());
    }
    std::sort(found.begin(), found.end());
    // A few: the stride below keeps each one's share of the time bounded.
    if (found.size() > 4) found.resize(4);
    files.insert(files.end(), found.begin(), found.end());
  }
  return files;
}

std::vector<std::string>* g_failures = nullptr;
void collect(const std::string& what) {
  if (g_failures->size() < 20) g_failures->push_back(what);
}

TEST(AllocationFailure, EveryFailedAllocationIsAnErrorAndTheNextCallsWork) {
  std::vector<std::string> failures;
  g_failures = &failures;
  fuzz::g_failure_handler = &collect;
  for (const fs::path& path : test_files()) {
    SCOPED_TRACE(path.string());
    const std::vector<uint8_t> file = testing::read_file_data(path);
    ASSERT_FALSE(file.empty());
    // Warm up once (one-time statics), then count the clean run's allocations.
    fuzz::DecodeRun clean;
    uint64_t allocations = 0;
    std::thread([&] {
      clean = fuzz::open_and_decode(file);
      allocations = fuzz::count_allocations(file);
    }).join();
    ASSERT_EQ(clean.open_code, ErrorCode::kOk);
    ASSERT_GT(allocations, 0u);
    // At most ~250 failure points a file, spread over the whole count.
    const uint64_t stride = std::max<uint64_t>(1, allocations / 250);
    int runs = 0, out_of_memory = 0;
    const auto start = std::chrono::steady_clock::now();
    for (uint64_t n = 1; n <= allocations; n += stride) {
      for (bool persistent : {false, true}) {
        if (persistent && (n - 1) / stride % 8 != 0) continue;  // every eighth point alone
        const int64_t live = fuzz::g_live_allocations.load();
        std::thread([&] { out_of_memory += fuzz::check_allocation_failure(file, clean, n, persistent); }).join();
        EXPECT_EQ(fuzz::g_live_allocations.load(), live)
            << "allocation " << n << (persistent ? " on" : "") << " leaked";
        ++runs;
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s: %llu allocations, stride %llu, %d runs, %d calls out of memory, %.1f s\n",
                path.filename().c_str(), static_cast<unsigned long long>(allocations),
                static_cast<unsigned long long>(stride), runs, out_of_memory, seconds);
    EXPECT_GT(out_of_memory, 0);
  }
  fuzz::g_failure_handler = nullptr;
  for (const std::string& failure : failures) ADD_FAILURE() << failure;
}

// The injection itself: the n-th allocation inside a library call fails, once or from
// there on; allocations outside calls are neither counted nor failed.
TEST(AllocationFailure, TheAllocatorFailsTheChosenAllocation) {
  fuzz::reset_allocation_count();
  fuzz::arm_allocation_failure(2, false);
  auto allocate = [] { return fuzz::library_call([] { return std::make_unique<int>(1); }); };
  EXPECT_NO_THROW(allocate());
  EXPECT_THROW(allocate(), std::bad_alloc);
  EXPECT_NO_THROW(allocate());
  EXPECT_NO_THROW(std::make_unique<int>(1));
  fuzz::arm_allocation_failure(1, true);
  EXPECT_THROW(allocate(), std::bad_alloc);
  EXPECT_THROW(allocate(), std::bad_alloc);
  EXPECT_EQ(fuzz::library_call([] { return new (std::nothrow) int(1); }), nullptr);
  fuzz::disarm_allocation_failure();
  EXPECT_NO_THROW(allocate());
  EXPECT_EQ(fuzz::t_allocator.counted, 7u);
  EXPECT_EQ(fuzz::t_allocator.failures, 4u);
}

}  // namespace
}  // namespace svc
