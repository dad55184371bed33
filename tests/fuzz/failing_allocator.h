// SPDX-License-Identifier: BSD-2-Clause
// Allocation-failure injection: the state a replaced global operator new consults, and
// the replacement itself (failing_allocator_new.h, included by exactly one source file of
// a program: the libFuzzer target svc_alloc_failure_fuzzer, the test program
// svc_alloc_failure_tests).
//
// Counting and failing are per thread, and only inside a LibraryCall scope: the
// allocations of the library's calls are counted and failed, not those the harness
// (libFuzzer, GoogleTest, the checks themselves) makes around them.
#pragma once

#include <atomic>
#include <cstdint>

namespace svc::fuzz {

struct FailingAllocatorState {
  bool active = false;  // inside a LibraryCall
  // Allocations left before the failing one: 1 makes the next allocation fail; 0 fails
  // none.
  uint64_t countdown = 0;
  // After the first failure, fail every allocation too (until disarmed).
  bool persistent = false;
  bool failing = false;   // the countdown has run out (and persistent is set)
  uint64_t counted = 0;   // allocations made in calls since reset_allocation_count()
  uint64_t failures = 0;  // allocations failed on purpose since then
};

inline thread_local FailingAllocatorState t_allocator;

// Live allocations (all threads): allocated minus freed, for leak checks outside
// LeakSanitizer.
inline std::atomic<int64_t> g_live_allocations{0};

// Makes this thread's `n`-th allocation from now on fail (n >= 1), and with `persistent`
// every one after it.
inline void arm_allocation_failure(uint64_t n, bool persistent) {
  t_allocator.countdown = n;
  t_allocator.persistent = persistent;
  t_allocator.failing = false;
}

inline void disarm_allocation_failure() {
  t_allocator.countdown = 0;
  t_allocator.persistent = false;
  t_allocator.failing = false;
}

inline void reset_allocation_count() {
  t_allocator.counted = 0;
  t_allocator.failures = 0;
}

// Marks this thread as inside a call of the library while it lives.
class LibraryCall {
 public:
  LibraryCall() { t_allocator.active = true; }
  ~LibraryCall() { t_allocator.active = false; }
  LibraryCall(const LibraryCall&) = delete;
  LibraryCall& operator=(const LibraryCall&) = delete;
};

// f() inside a LibraryCall scope (its result is built inside it too).
template <typename F>
auto library_call(F&& f) {
  LibraryCall scope;
  return f();
}

// Called by the replaced operator new for each allocation: whether it must fail.
inline bool allocation_must_fail() {
  FailingAllocatorState& s = t_allocator;
  if (!s.active) return false;
  ++s.counted;
  bool fail = s.failing;
  if (!fail && s.countdown != 0 && --s.countdown == 0) {
    fail = true;
    s.failing = s.persistent;
  }
  s.failures += fail;
  return fail;
}

}  // namespace svc::fuzz
