// SPDX-License-Identifier: BSD-2-Clause
// libFuzzer target: an .svc file decoded by a reader with prefetch, decode threads and
// small caches from four threads at once, one of which closes it part-way; every result
// must be the sequential decode's (tests/fuzz/reader_entry.h).
#include "fuzz/reader_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  svc::fuzz::run_threads_input(std::span<const uint8_t>(data, size));
  return 0;
}
