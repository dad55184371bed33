// SPDX-License-Identifier: BSD-2-Clause
// Objects kept per thread and destroyed when their thread ends, without a C++ thread_local
// that has a destructor. With MinGW-w64's emulated TLS, the storage of such a thread_local
// is freed before its destructor runs at thread exit, so the destructor reads freed memory
// and may free blocks twice (a known toolchain fault; under Wine, 398 of 400 destructors
// of a probe saw their storage already overwritten). The library therefore declares no
// thread_local (scripts/check-layers.sh); it keeps each thread's object in the operating
// system's thread-specific storage (POSIX keys, Windows fiber-local storage), whose exit
// callback is handed the object itself.
#pragma once

#include <cstdint>
#include <memory>

namespace svc::codec {

// What a slot holds: deleted through this base when its thread ends.
class ThreadOwned {
 public:
  ThreadOwned() = default;
  ThreadOwned(const ThreadOwned&) = delete;
  ThreadOwned& operator=(const ThreadOwned&) = delete;
  virtual ~ThreadOwned() = default;
};

// One key of thread-specific storage. Thread-safe: each thread sees its own object.
// Slots are never destroyed, since threads may end after static destruction.
class ThreadSlot {
 public:
  // Throws std::system_error when the system has no key left.
  ThreadSlot();
  ThreadSlot(const ThreadSlot&) = delete;
  ThreadSlot& operator=(const ThreadSlot&) = delete;

  // The calling thread's object, or null before its first set().
  ThreadOwned* get() const noexcept;
  // Hands the calling thread's object to the slot, which deletes it when the thread ends.
  // Call once per thread. Throws std::bad_alloc (deleting the object) when the system
  // cannot store it.
  void set(std::unique_ptr<ThreadOwned> object);

 private:
  uint64_t key_ = 0;
};

// The calling thread's T: default-constructed on the thread's first call, destroyed
// when the thread ends. Throws what T's constructor or the allocation throws; a later
// call retries.
template <class T>
T& thread_object() {
  struct Holder final : ThreadOwned {
    T value{};
  };
  static ThreadSlot* const slot = new ThreadSlot();
  if (ThreadOwned* held = slot->get()) return static_cast<Holder*>(held)->value;
  auto holder = std::make_unique<Holder>();
  T& value = holder->value;
  slot->set(std::move(holder));
  return value;
}

}  // namespace svc::codec
