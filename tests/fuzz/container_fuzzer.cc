// SPDX-License-Identifier: BSD-2-Clause
// libFuzzer target: an .svc file from arbitrary bytes, opened and fully decoded.
#include "fuzz/fuzz_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  svc::fuzz::run_container_input(std::span<const uint8_t>(data, size));
  return 0;
}
