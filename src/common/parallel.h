// SPDX-License-Identifier: BSD-2-Clause
// The project's one way to run work on several threads (encoder, bench, scene
// generator): parallel_for for independent items, ordered_parallel_map when results must
// be consumed in order. Results, and the bytes written from them, never depend on the
// thread count.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/exception_status.h"
#include "svc/status.h"

namespace svc {

inline int resolve_thread_count(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

// Runs body(i) for every i in [0, count) on up to `threads` threads (the caller's among
// them). After an error no new item starts; the error of the lowest failed index is
// returned, so which error comes back does not depend on timing either. An exception
// thrown by body(i) is item i's error (svc/common/exception_status.h: kOutOfMemory for a
// failed allocation), on a helper thread as on the caller's. When a helper thread cannot
// be started, the items run on the threads that did start.
inline Status parallel_for(size_t count, int threads, const std::function<Status(size_t)>& body) {
  std::atomic<size_t> next{0};
  std::mutex mutex;
  size_t failed_index = count;
  Status first_error;
  auto worker = [&] {
    for (size_t i = next++; i < count; i = next++) {
      Status status = status_guarded([&] { return "item " + std::to_string(i); }, [&] { return body(i); });
      if (status.ok()) continue;
      std::lock_guard<std::mutex> lock(mutex);
      if (i < failed_index) {
        failed_index = i;
        first_error = std::move(status);
      }
      next = count;
    }
  };
  const int n = std::max(1, std::min<int>(threads, static_cast<int>(std::min<size_t>(count, 1024))));
  std::vector<std::thread> pool;
  try {
    pool.reserve(static_cast<size_t>(n - 1));
    for (int t = 1; t < n; ++t) pool.emplace_back(worker);
  } catch (...) {
    // No memory or no thread left: the threads started (maybe none) do the work.
  }
  worker();
  for (auto& thread : pool) thread.join();
  return first_error;
}

// produce(i) runs on a worker; consume(i, value) runs on the caller's thread in order
// 0..count-1. At most `window` produced values wait to be consumed. The first error
// (from produce or consume, lowest index first) stops the work and is returned. An
// exception thrown by produce(i) or consume(i, ...) is item i's error, as in
// parallel_for; so is a value that cannot be kept for want of memory. When no helper
// thread can be started, the items run on the caller's thread.
template <typename T>
Status ordered_parallel_map(size_t count, int threads, const std::function<Result<T>(size_t)>& produce,
                            const std::function<Status(size_t, T&)>& consume) {
  auto item = [](size_t i) { return "item " + std::to_string(i); };
  auto produce_guarded = [&](size_t i) {
    return status_guarded([&] { return item(i); }, [&] { return produce(i); });
  };
  auto consume_guarded = [&](size_t i, T& value) {
    return status_guarded([&] { return item(i); }, [&] { return consume(i, value); });
  };
  auto serial = [&] {
    for (size_t i = 0; i < count; ++i) {
      Result<T> value = produce_guarded(i);
      if (!value.ok()) return value.status();
      SVC_RETURN_IF_ERROR(consume_guarded(i, *value));
    }
    return Status::Ok();
  };
  threads = std::max(1, std::min<int>(threads, static_cast<int>(std::max<size_t>(count, 1))));
  if (threads == 1) return serial();
  const size_t window = static_cast<size_t>(threads) * 4;
  std::mutex mutex;
  std::condition_variable cv;
  std::map<size_t, Result<T>> ready;
  size_t next_to_claim = 0;
  size_t next_to_consume = 0;
  size_t lost = count;  // the lowest item whose value could not be kept
  bool stop = false;

  auto worker = [&] {
    for (;;) {
      size_t i;
      {
        std::unique_lock lock(mutex);
        cv.wait(lock, [&] { return stop || next_to_claim >= count || next_to_claim < next_to_consume + window; });
        if (stop || next_to_claim >= count) return;
        i = next_to_claim++;
      }
      Result<T> value = produce_guarded(i);
      {
        std::lock_guard lock(mutex);
        try {
          ready.emplace(i, std::move(value));
        } catch (...) {
          lost = std::min(lost, i);
          stop = true;
        }
      }
      cv.notify_all();
    }
  };
  std::vector<std::thread> pool;
  try {
    pool.reserve(static_cast<size_t>(threads));
    for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  } catch (...) {
    // No memory or no thread left: the threads started do the work.
  }
  if (pool.empty()) return serial();

  Status result;
  while (next_to_consume < count) {
    std::optional<Result<T>> value;
    {
      std::unique_lock lock(mutex);
      cv.wait(lock, [&] { return ready.count(next_to_consume) != 0 || lost <= next_to_consume; });
      if (ready.count(next_to_consume) != 0) value.emplace(std::move(ready.extract(next_to_consume).mapped()));
    }
    Status status;
    if (!value.has_value()) {
      status =
          status_guarded([&] { return item(next_to_consume); },
                         [&] {
                           return Status(ErrorCode::kOutOfMemory,
                                         item(next_to_consume) + ": out of memory (its value could not be kept)");
                         });
    } else {
      status = value->ok() ? consume_guarded(next_to_consume, **value) : value->status();
    }
    {
      std::lock_guard lock(mutex);
      ++next_to_consume;
      if (!status.ok()) stop = true;
    }
    cv.notify_all();
    if (!status.ok()) {
      result = std::move(status);
      break;
    }
  }
  for (auto& t : pool) t.join();
  return result;
}

}  // namespace svc
