// SPDX-License-Identifier: BSD-2-Clause
// libFuzzer target: one I-face or B-face payload of a small size (fuzz_entry.h).
#include "fuzz/fuzz_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  svc::fuzz::run_frame_input(std::span<const uint8_t>(data, size));
  return 0;
}
