// SPDX-License-Identifier: BSD-2-Clause
// Replaces the global operator new and delete (plain, array, nothrow, aligned and sized
// forms) with ones that consult failing_allocator.h. Include in exactly one source file
// of a program: replacement functions may not be inline.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>

#include "fuzz/failing_allocator.h"

namespace svc::fuzz::allocator_detail {

inline void* allocate(std::size_t size, std::size_t alignment) noexcept {
  if (allocation_must_fail()) return nullptr;
  if (size == 0) size = 1;
  void* p = nullptr;
  if (alignment <= alignof(std::max_align_t)) {
    p = std::malloc(size);
  } else if (::posix_memalign(&p, alignment, size) != 0) {
    p = nullptr;
  }
  if (p != nullptr) g_live_allocations.fetch_add(1, std::memory_order_relaxed);
  return p;
}

inline void release(void* p) noexcept {
  if (p == nullptr) return;
  g_live_allocations.fetch_sub(1, std::memory_order_relaxed);
  std::free(p);
}

inline void* allocate_or_throw(std::size_t size, std::size_t alignment) {
  if (void* p = allocate(size, alignment)) return p;
  throw std::bad_alloc();
}

}  // namespace svc::fuzz::allocator_detail

// NOLINTBEGIN: the replaceable allocation functions, as the standard names them.
void* operator new(std::size_t size) { return svc::fuzz::allocator_detail::allocate_or_throw(size, 0); }
void* operator new[](std::size_t size) { return svc::fuzz::allocator_detail::allocate_or_throw(size, 0); }
void* operator new(std::size_t size, std::align_val_t a) {
  return svc::fuzz::allocator_detail::allocate_or_throw(size, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t size, std::align_val_t a) {
  return svc::fuzz::allocator_detail::allocate_or_throw(size, static_cast<std::size_t>(a));
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return svc::fuzz::allocator_detail::allocate(size, 0);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return svc::fuzz::allocator_detail::allocate(size, 0);
}
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return svc::fuzz::allocator_detail::allocate(size, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return svc::fuzz::allocator_detail::allocate(size, static_cast<std::size_t>(a));
}
void operator delete(void* p) noexcept { svc::fuzz::allocator_detail::release(p); }
void operator delete[](void* p) noexcept { svc::fuzz::allocator_detail::release(p); }
void operator delete(void* p, std::size_t) noexcept { svc::fuzz::allocator_detail::release(p); }
void operator delete[](void* p, std::size_t) noexcept { svc::fuzz::allocator_detail::release(p); }
void operator delete(void* p, std::align_val_t) noexcept { svc::fuzz::allocator_detail::release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { svc::fuzz::allocator_detail::release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { svc::fuzz::allocator_detail::release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { svc::fuzz::allocator_detail::release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { svc::fuzz::allocator_detail::release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { svc::fuzz::allocator_detail::release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  svc::fuzz::allocator_detail::release(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  svc::fuzz::allocator_detail::release(p);
}
// NOLINTEND
