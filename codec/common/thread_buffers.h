// SPDX-License-Identifier: BSD-2-Clause
// The working buffers that decoding keeps per thread (the B-face decoder's state, CDEF's
// widened planes) are reused from face to face and live as long as their thread; they
// belong to no cache. Each thread counts its share in one process-wide total, which the
// reader reports (ReaderStats::thread_buffer_bytes).
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "codec/common/thread_slot.h"

namespace svc::codec {

// Bytes held by the working buffers of every live thread of the process.
inline std::atomic<int64_t> thread_buffer_total{0};

inline uint64_t thread_buffer_bytes() {
  const int64_t total = thread_buffer_total.load(std::memory_order_relaxed);
  return total > 0 ? static_cast<uint64_t>(total) : 0;
}

// One thread's share of the total for one set of buffers: set after they change size,
// taken out of the total when the thread ends. Not shared between threads.
class ThreadBufferShare {
 public:
  ThreadBufferShare() = default;
  ThreadBufferShare(const ThreadBufferShare&) = delete;
  ThreadBufferShare& operator=(const ThreadBufferShare&) = delete;
  ~ThreadBufferShare() { thread_buffer_total.fetch_sub(bytes_, std::memory_order_relaxed); }
  void set(uint64_t bytes) {
    if (static_cast<int64_t>(bytes) == bytes_) return;
    thread_buffer_total.fetch_add(static_cast<int64_t>(bytes) - bytes_, std::memory_order_relaxed);
    bytes_ = static_cast<int64_t>(bytes);
  }

 private:
  int64_t bytes_ = 0;
};

// One kind of working buffers of the calling thread, with their share of the total; both
// go when the thread ends.
template <class Buffers>
struct ThreadBuffers {
  Buffers buffers{};
  ThreadBufferShare share;
};

template <class Buffers>
ThreadBuffers<Buffers>& thread_buffers() {
  return thread_object<ThreadBuffers<Buffers>>();
}

template <class T>
uint64_t capacity_bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace svc::codec
