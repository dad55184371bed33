// SPDX-License-Identifier: BSD-2-Clause
// The Status an exception stands for, for code that must not let one escape: the
// reader's public calls, its prefetch workers and the helper threads of parallel_for. A
// failed allocation (std::bad_alloc) is kOutOfMemory; anything else thrown is kInternal,
// a broken invariant.
#pragma once

#include <exception>
#include <new>
#include <string>
#include <utility>

#include "svc/status.h"

namespace svc {

// Call from inside a catch block only. `context()` returns what was being done (e.g.
// "decode_face of cell (1,0,2) face +x in f.svc"); the message is "<context>: out of
// memory" or "<context>: <what()>". Never throws: when the message cannot be built
// either (memory is that short), the code comes back with an empty message.
template <typename Context>
Status current_exception_status(Context&& context) noexcept {
  ErrorCode code = ErrorCode::kInternal;
  try {
    std::string detail;
    try {
      throw;
    } catch (const std::bad_alloc&) {
      code = ErrorCode::kOutOfMemory;
      detail = "out of memory";
    } catch (const std::exception& e) {
      detail = e.what();
    } catch (...) {
      detail = "unknown exception";
    }
    return Status(code, std::forward<Context>(context)() + ": " + detail);
  } catch (...) {
    return Status(code, std::string());
  }
}

// body() (returning a Status or a Result<T>) with any exception it throws turned into
// that Status, naming `context()`.
template <typename Context, typename Body>
auto status_guarded(Context&& context, Body&& body) noexcept -> decltype(body()) {
  try {
    return body();
  } catch (...) {
    return current_exception_status(std::forward<Context>(context));
  }
}

}  // namespace svc
