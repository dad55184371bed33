// SPDX-License-Identifier: BSD-2-Clause
// The one thread pool (common/parallel.h): every item runs once, results are consumed in
// order, and which error comes back does not depend on the thread count or timing.
#include "common/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <new>
#include <stdexcept>
#include <vector>

namespace svc {
namespace {

TEST(Parallel, ForRunsEveryItemOnce) {
  for (int threads : {1, 3, 8}) {
    std::vector<std::atomic<int>> runs(257);
    const Status status = parallel_for(runs.size(), threads, [&](size_t i) {
      runs[i].fetch_add(1);
      return Status::Ok();
    });
    ASSERT_TRUE(status.ok());
    for (size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(runs[i].load(), 1) << "item " << i << ", " << threads;
  }
}

TEST(Parallel, ForReturnsTheLowestFailedItemsError) {
  for (int attempt = 0; attempt < 20; ++attempt) {
    for (int threads : {1, 4}) {
      const Status status = parallel_for(200, threads, [](size_t i) {
        if (i == 37 || i == 150) return Status(ErrorCode::kBadInput, "item " + std::to_string(i));
        return Status::Ok();
      });
      ASSERT_EQ(status.code(), ErrorCode::kBadInput);
      EXPECT_EQ(status.message(), "item 37");
    }
  }
}

TEST(Parallel, OrderedMapConsumesInIndexOrder) {
  std::vector<size_t> consumed;
  const Status status = ordered_parallel_map<size_t>(
      100, 4, [](size_t i) -> Result<size_t> { return i * i; },
      [&](size_t i, size_t& value) {
        EXPECT_EQ(value, i * i);
        consumed.push_back(i);
        return Status::Ok();
      });
  ASSERT_TRUE(status.ok());
  ASSERT_EQ(consumed.size(), 100u);
  for (size_t i = 0; i < consumed.size(); ++i) EXPECT_EQ(consumed[i], i);
}

TEST(Parallel, OrderedMapTurnsExceptionsIntoTheLowestItemsError) {
  for (int threads : {1, 4}) {
    std::vector<size_t> consumed;
    const Status status = ordered_parallel_map<size_t>(
        100, threads,
        [](size_t i) -> Result<size_t> {
          if (i == 37 || i == 80) throw std::bad_alloc();
          if (i == 60) throw std::runtime_error("broken");
          return i;
        },
        [&](size_t i, size_t&) {
          consumed.push_back(i);
          return Status::Ok();
        });
    EXPECT_EQ(status.code(), ErrorCode::kOutOfMemory) << threads;
    EXPECT_EQ(status.message(), "item 37: out of memory") << threads;
    ASSERT_EQ(consumed.size(), 37u) << threads;  // every item before the failed one, in order
    for (size_t i = 0; i < consumed.size(); ++i) EXPECT_EQ(consumed[i], i);
  }
}

TEST(Parallel, OrderedMapTurnsAConsumersExceptionIntoItsError) {
  for (int threads : {1, 3}) {
    const Status status = ordered_parallel_map<size_t>(
        50, threads, [](size_t i) -> Result<size_t> { return i; },
        [](size_t i, size_t&) -> Status {
          if (i == 12) throw std::runtime_error("no room");
          return Status::Ok();
        });
    EXPECT_EQ(status.code(), ErrorCode::kInternal) << threads;
    EXPECT_EQ(status.message(), "item 12: no room") << threads;
  }
}

}  // namespace
}  // namespace svc
