// SPDX-License-Identifier: BSD-2-Clause
#include "command_line/report.h"

#include <cstdio>

#include "command_line/command_line.h"
#include "command_line/interrupt.h"

namespace svc::command_line {

int exit_code_for(const Status& status) {
  switch (status.code()) {
    case ErrorCode::kOk: return kExitOk;
    case ErrorCode::kInvalidArgument: return kExitUsage;
    case ErrorCode::kCorruptData: return kExitCorrupt;
    default: return kExitFailure;
  }
}

int report_failure(const char* program, const Status& status) {
  if (interrupted()) {
    std::fprintf(stderr, "%s: stopped by %s; nothing was written\n", program, interrupting_signal_name());
    return interrupted_exit_code();
  }
  std::fprintf(stderr, "%s: %s\n", program, status.to_string().c_str());
  return exit_code_for(status);
}

}  // namespace svc::command_line
