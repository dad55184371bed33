// SPDX-License-Identifier: BSD-2-Clause
// A thread-safe least-recently-used cache of immutable values under a byte budget,
// with in-flight deduplication: the first thread to ask for a missing key computes it
// while later askers wait for that result instead of computing it again.
//
// Threading: every method may be called from any number of threads. The compute
// function runs without the cache's lock held, so it may use other caches (it must not
// wait on a key of this same cache, which could deadlock). Values are handed out as
// shared_ptr<const V>: eviction never invalidates a value a caller still holds.
// Errors from compute are passed to every waiter and not cached; so is an exception it
// throws (as kOutOfMemory for a failed allocation, else kInternal), after which the key
// is computed again on the next request.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <unordered_map>
#include <utility>

#include "common/exception_status.h"
#include "svc/reader.h"
#include "svc/status.h"

namespace svc::reader_internal {

enum class Origin : uint8_t { kCaller = 0, kPrefetch = 1 };

// What one get() call did, for the caller's own accounting.
enum class Outcome : uint8_t { kHit = 0, kComputed = 1, kWaited = 2 };

template <typename Value>
class SharedCache {
 public:
  using Pointer = std::shared_ptr<const Value>;
  // Bookkeeping charged per entry on top of the value's own bytes (map and list nodes).
  static constexpr uint64_t kEntryOverhead = 96;

  SharedCache(uint64_t budget_bytes, uint64_t (*value_bytes)(const Value&))
      : budget_(budget_bytes), value_bytes_(value_bytes) {}
  SharedCache(const SharedCache&) = delete;
  SharedCache& operator=(const SharedCache&) = delete;

  // The value for `key`: from the cache, from a computation already in flight, or from
  // `compute` (a callable returning Result<Pointer>) run on this thread.
  template <typename Compute>
  Result<Pointer> get(uint32_t key, Origin origin, Compute&& compute, Outcome* outcome = nullptr) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (origin == Origin::kPrefetch) ++counters_.prefetch_lookups;
    if (auto it = entries_.find(key); it != entries_.end()) {
      lru_.splice(lru_.begin(), lru_, it->second.position);
      if (origin == Origin::kCaller) ++counters_.hits;
      if (outcome) *outcome = Outcome::kHit;
      return it->second.value;
    }
    if (auto it = in_flight_.find(key); it != in_flight_.end()) {
      std::shared_ptr<InFlight> pending = it->second;
      if (origin == Origin::kCaller) ++counters_.in_flight_waits;
      done_.wait(lock, [&] { return pending->done; });
      if (outcome) *outcome = Outcome::kWaited;
      if (!pending->status.ok()) return pending->status;
      return pending->value;
    }
    if (origin == Origin::kCaller) ++counters_.misses;
    // Nothing is registered if this throws (out of memory): the caller's guard reports it.
    auto pending = std::make_shared<InFlight>();
    in_flight_.emplace(key, pending);
    lock.unlock();

    // From here every path publishes an outcome and releases the in-flight entry, so that
    // waiters wake and a later call computes again: an exception thrown by `compute` is
    // its error, and a value that cannot be inserted is returned uncached.
    Result<Pointer> computed =
        status_guarded([] { return std::string("decoding"); }, [&]() -> Result<Pointer> { return compute(); });
    Status published = computed.ok() ? Status::Ok() : copy_or_code(computed.status());

    lock.lock();
    if (computed.ok()) {
      pending->value = *computed;
      try {
        insert_locked(key, *computed);
      } catch (...) {
        // No memory for the entry's bookkeeping: the value is handed out, not cached.
      }
    } else {
      pending->status = std::move(published);
    }
    pending->done = true;
    in_flight_.erase(key);
    lock.unlock();
    done_.notify_all();
    if (outcome) *outcome = Outcome::kComputed;
    return computed;
  }

  // The value when cached (refreshing its recency), else null. Counts nothing and never
  // waits.
  Pointer peek(uint32_t key) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = entries_.find(key);
    if (it == entries_.end()) return nullptr;
    lru_.splice(lru_.begin(), lru_, it->second.position);
    return it->second.value;
  }

  bool contains(uint32_t key) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return entries_.count(key) != 0;
  }

  // Evicts down to the new budget (0 empties the cache and stops insertions).
  void set_budget(uint64_t budget_bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    budget_ = budget_bytes;
    evict_to_locked(budget_);
  }

  uint64_t entry_bytes(const Value& value) const { return value_bytes_(value) + kEntryOverhead; }

  CacheCounters counters() const {
    std::lock_guard<std::mutex> lock(mutex_);
    CacheCounters c = counters_;
    c.entries = entries_.size();
    c.bytes_held = bytes_held_;
    c.budget_bytes = budget_;
    return c;
  }

 private:
  struct Entry {
    Pointer value;
    uint64_t bytes = 0;
    std::list<uint32_t>::iterator position;  // in lru_
  };
  struct InFlight {
    bool done = false;
    Status status;
    Pointer value;
  };

  // A copy of `status` for the waiters; its code alone when the message cannot be copied.
  static Status copy_or_code(const Status& status) noexcept {
    try {
      return status;
    } catch (...) {
      return Status(status.code(), std::string());
    }
  }

  // Strong guarantee: when an allocation fails (an exception), the cache is as before
  // but for the entries evicted to make room.
  void insert_locked(uint32_t key, const Pointer& value) {
    const uint64_t bytes = entry_bytes(*value);
    if (bytes > budget_ || entries_.count(key) != 0) return;
    evict_to_locked(budget_ - bytes);
    lru_.push_front(key);
    try {
      entries_.emplace(key, Entry{value, bytes, lru_.begin()});
    } catch (...) {
      lru_.pop_front();
      throw;
    }
    bytes_held_ += bytes;
    ++counters_.insertions;
    if (bytes_held_ > counters_.peak_bytes) counters_.peak_bytes = bytes_held_;
  }

  void evict_to_locked(uint64_t limit) {
    while (bytes_held_ > limit && !lru_.empty()) {
      const uint32_t victim = lru_.back();
      lru_.pop_back();
      auto it = entries_.find(victim);
      bytes_held_ -= it->second.bytes;
      entries_.erase(it);
      ++counters_.evictions;
    }
  }

  mutable std::mutex mutex_;
  std::condition_variable done_;
  uint64_t budget_;
  uint64_t (*value_bytes_)(const Value&);
  uint64_t bytes_held_ = 0;
  std::unordered_map<uint32_t, Entry> entries_;
  std::list<uint32_t> lru_;  // front: most recently used
  std::unordered_map<uint32_t, std::shared_ptr<InFlight>> in_flight_;
  CacheCounters counters_;
};

}  // namespace svc::reader_internal
