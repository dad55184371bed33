// SPDX-License-Identifier: BSD-2-Clause
// ThreadSlot on POSIX threads: a key whose destructor deletes the thread's object.
#include <pthread.h>

#include <new>
#include <system_error>

#include "codec/common/thread_slot.h"

namespace svc::codec {

namespace {

extern "C" void delete_thread_owned(void* object) { delete static_cast<ThreadOwned*>(object); }

}  // namespace

ThreadSlot::ThreadSlot() {
  pthread_key_t key;
  if (const int error = pthread_key_create(&key, delete_thread_owned); error != 0) {
    throw std::system_error(error, std::generic_category(), "thread-specific storage key");
  }
  key_ = static_cast<uint64_t>(key);
}

ThreadOwned* ThreadSlot::get() const noexcept {
  return static_cast<ThreadOwned*>(pthread_getspecific(static_cast<pthread_key_t>(key_)));
}

void ThreadSlot::set(std::unique_ptr<ThreadOwned> object) {
  if (pthread_setspecific(static_cast<pthread_key_t>(key_), object.get()) != 0) throw std::bad_alloc();
  (void)object.release();
}

}  // namespace svc::codec
