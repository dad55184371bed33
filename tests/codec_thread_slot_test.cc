// SPDX-License-Identifier: BSD-2-Clause
// Per-thread objects (codec/common/thread_slot.h): one per thread, the same on every call,
// destroyed intact when the thread ends. The Windows build runs this under Wine
// (scripts/check-windows.sh), where a C++ thread_local's storage is freed before its
// destructor runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <latch>
#include <set>
#include <thread>
#include <vector>

#include "codec/common/thread_buffers.h"
#include "codec/common/thread_slot.h"

namespace svc::codec {
namespace {

constexpr unsigned char kPattern = 0x5a;
std::atomic<int> probes_destroyed{0};
std::atomic<int> probes_intact{0};

struct Probe {
  Probe() { bytes.fill(kPattern); }
  Probe(const Probe&) = delete;
  Probe& operator=(const Probe&) = delete;
  ~Probe() {
    ++probes_destroyed;
    if (std::all_of(bytes.begin(), bytes.end(), [](unsigned char b) { return b == kPattern; })) ++probes_intact;
  }
  std::array<unsigned char, 64> bytes{};
};

TEST(ThreadSlot, EachThreadHasOneObjectDestroyedIntactWhenTheThreadEnds) {
  probes_destroyed = 0;
  probes_intact = 0;
  constexpr int kRounds = 25, kThreads = 4;
  for (int round = 0; round < kRounds; ++round) {
    std::array<const Probe*, kThreads> seen{};
    std::latch all_made(kThreads);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
      threads.emplace_back([&, t] {
        const Probe& first = thread_object<Probe>();
        seen[t] = &first;
        all_made.arrive_and_wait();                 // every thread's object alive at once
        std::vector<unsigned char> churn(4096, 1);  // heap traffic that would reuse freed storage
        EXPECT_EQ(&thread_object<Probe>(), &first);
        EXPECT_EQ(churn[100], 1);
      });
    }
    for (std::thread& thread : threads) thread.join();
    EXPECT_EQ(std::set<const Probe*>(seen.begin(), seen.end()).size(), static_cast<size_t>(kThreads));
  }
  EXPECT_EQ(probes_destroyed.load(), kRounds * kThreads);
  EXPECT_EQ(probes_intact.load(), kRounds * kThreads);
}

TEST(ThreadSlot, WorkingBuffersLeaveTheTotalWithTheirThread) {
  const uint64_t before = thread_buffer_bytes();
  uint64_t during = 0;
  std::thread worker([&] {
    ThreadBuffers<std::vector<uint16_t>>& thread = thread_buffers<std::vector<uint16_t>>();
    thread.buffers.resize(10000);
    thread.share.set(capacity_bytes(thread.buffers));
    during = thread_buffer_bytes();
  });
  worker.join();
  EXPECT_GE(during, before + 20000);
  EXPECT_EQ(thread_buffer_bytes(), before);
}

}  // namespace
}  // namespace svc::codec
