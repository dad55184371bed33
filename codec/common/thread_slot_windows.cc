// SPDX-License-Identifier: BSD-2-Clause
// ThreadSlot on Windows: a fiber-local storage index whose callback deletes the thread's
// object when the thread ends, for threads of any origin (CreateThread, the C runtime,
// winpthreads).
#include <windows.h>

#include <new>
#include <system_error>

#include "codec/common/thread_slot.h"

namespace svc::codec {

namespace {

VOID NTAPI delete_thread_owned(PVOID object) { delete static_cast<ThreadOwned*>(object); }

}  // namespace

ThreadSlot::ThreadSlot() {
  // Pinned, when built into a DLL: the callback must outlive every thread that used it.
  HMODULE module = nullptr;
  (void)GetModuleHandleExW(GET_MODULE_HANDLE_EX_FLAG_FROM_ADDRESS | GET_MODULE_HANDLE_EX_FLAG_PIN,
                           reinterpret_cast<LPCWSTR>(&delete_thread_owned), &module);
  const DWORD index = FlsAlloc(delete_thread_owned);
  if (index == FLS_OUT_OF_INDEXES) {
    throw std::system_error(static_cast<int>(GetLastError()), std::system_category(), "fiber-local storage index");
  }
  key_ = index;
}

ThreadOwned* ThreadSlot::get() const noexcept {
  return static_cast<ThreadOwned*>(FlsGetValue(static_cast<DWORD>(key_)));
}

void ThreadSlot::set(std::unique_ptr<ThreadOwned> object) {
  if (!FlsSetValue(static_cast<DWORD>(key_), object.get())) throw std::bad_alloc();
  (void)object.release();
}

}  // namespace svc::codec
