// SPDX-License-Identifier: BSD-2-Clause
// Error values used across the svc API. No svc function throws across the public
// API boundary: failures come back as a Status (or a Result<T> holding one).
#pragma once

#include <optional>
#include <string>
#include <utility>

#include "svc/export.h"

namespace svc {

enum class ErrorCode : int {
  kOk = 0,
  kInvalidArgument,  // a caller-supplied setting or argument is out of range
  kNotFound,         // a file, cell or face that does not exist
  kIoError,          // the operating system refused a read or write
  kBadInput,         // an svc-input database that breaks docs/input-format.md
  kCorruptData,      // an .svc file whose bytes fail validation (CRC, bounds, syntax)
  kLimitExceeded,    // a size above a configured cap
  kUnsupported,      // a valid file using a feature this build cannot decode
  kCancelled,        // the operation was cancelled (reader closed, callback asked)
  kInternal,         // a broken invariant inside svc; please report it
  kOutOfMemory,      // an allocation failed; the object that reports it stays usable
};

SVC_API const char* error_code_name(ErrorCode code) noexcept;

// A success or an error code with a human-readable message that names what is
// wrong and where (file, cell, face, byte offset). Cheap to copy when ok.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(ErrorCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status Ok() { return Status(); }

  bool ok() const noexcept { return code_ == ErrorCode::kOk; }
  ErrorCode code() const noexcept { return code_; }
  const std::string& message() const noexcept { return message_; }
  // "<code name>: <message>", or "ok".
  SVC_API std::string to_string() const;

  // Returns a copy whose message is prefixed with `context + ": "`.
  SVC_API Status with_context(const std::string& context) const;

 private:
  ErrorCode code_ = ErrorCode::kOk;
  std::string message_;
};

// Either a value or a non-ok Status.
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : value_(std::move(value)) {}         // NOLINT: implicit by design
  Result(Status status) : status_(std::move(status)) {  // NOLINT: implicit by design
    if (status_.ok()) status_ = Status(ErrorCode::kInternal, "Result constructed from ok Status");
  }

  bool ok() const noexcept { return status_.ok(); }
  const Status& status() const noexcept { return status_; }

  // Precondition: ok().
  T& value() & { return *value_; }
  const T& value() const& { return *value_; }
  T&& value() && { return std::move(*value_); }
  T* operator->() { return &*value_; }
  const T* operator->() const { return &*value_; }
  T& operator*() & { return *value_; }
  const T& operator*() const& { return *value_; }

 private:
  Status status_;
  std::optional<T> value_;
};

}  // namespace svc

#define SVC_STATUS_CONCAT_INNER(a, b) a##b
#define SVC_STATUS_CONCAT(a, b) SVC_STATUS_CONCAT_INNER(a, b)

// Returns the Status from the enclosing function when `expr` is not ok.
#define SVC_RETURN_IF_ERROR(expr)                      \
  do {                                                 \
    ::svc::Status svc_status_tmp_ = (expr);            \
    if (!svc_status_tmp_.ok()) return svc_status_tmp_; \
  } while (0)

// `lhs = value of expr`, or returns its Status from the enclosing function.
#define SVC_ASSIGN_OR_RETURN(lhs, expr) \
  SVC_ASSIGN_OR_RETURN_IMPL(SVC_STATUS_CONCAT(svc_result_tmp_, __LINE__), lhs, expr)
#define SVC_ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr) \
  auto tmp = (expr);                              \
  if (!tmp.ok()) return tmp.status();             \
  lhs = std::move(tmp).value()
