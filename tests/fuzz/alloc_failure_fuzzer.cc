// SPDX-License-Identifier: BSD-2-Clause
// libFuzzer target: an .svc file opened and decoded through svc::Reader while one of its
// allocations fails (or every one from some point on): each call returns an error or
// exactly the clean decode's result, nothing leaks (LeakSanitizer), and the same reader
// then decodes exactly as the clean run (tests/fuzz/reader_entry.h).
#include "fuzz/failing_allocator_new.h"
#include "fuzz/reader_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  svc::fuzz::run_alloc_failure_input(std::span<const uint8_t>(data, size));
  return 0;
}
