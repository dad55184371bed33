// Ordered parallel map: items are computed by worker threads in any order and handed
// to a consumer on the calling thread strictly in index order, so results (and the
// bytes written from them) never depend on the thread count.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "svc/status.h"

namespace svc {

inline int resolve_thread_count(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

// produce(i) runs on a worker; consume(i, value) runs on the caller's thread in order
// 0..count-1. At most `window` produced values wait to be consumed. The first error
// (from produce or consume, lowest index first) stops the work and is returned.
template <typename T>
Status ordered_parallel_map(size_t count, int threads, const std::function<Result<T>(size_t)>& produce,
                            const std::function<Status(size_t, T&)>& consume) {
  threads = std::max(1, std::min<int>(threads, static_cast<int>(std::max<size_t>(count, 1))));
  if (threads == 1) {
    for (size_t i = 0; i < count; ++i) {
      Result<T> value = produce(i);
      if (!value.ok()) return value.status();
      SVC_RETURN_IF_ERROR(consume(i, *value));
    }
    return Status::Ok();
  }
  const size_t window = static_cast<size_t>(threads) * 4;
  std::mutex mutex;
  std::condition_variable cv;
  std::map<size_t, Result<T>> ready;
  size_t next_to_claim = 0;
  size_t next_to_consume = 0;
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
      Result<T> value = produce(i);
      {
        std::lock_guard lock(mutex);
        ready.emplace(i, std::move(value));
      }
      cv.notify_all();
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(threads);
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker);

  Status result;
  while (next_to_consume < count) {
    std::optional<Result<T>> value;
    {
      std::unique_lock lock(mutex);
      cv.wait(lock, [&] { return ready.count(next_to_consume) != 0; });
      auto node = ready.extract(next_to_consume);
      value.emplace(std::move(node.mapped()));
    }
    Status status = value->ok() ? consume(next_to_consume, **value) : value->status();
    {
      std::lock_guard lock(mutex);
      ++next_to_consume;
      if (!status.ok()) stop = true;
    }
    cv.notify_all();
    if (!status.ok()) {
      result = status;
      break;
    }
  }
  for (auto& t : pool) t.join();
  return result;
}

}  // namespace svc
