// SPDX-License-Identifier: BSD-2-Clause
// How svc, svc-scene and svc-walkthrough report a failed command: one line
// "PROGRAM: message" on stderr and the exit status of command_line.h for its error code.
#pragma once

#include "svc/status.h"

namespace svc::command_line {

// The exit status for an error: kInvalidArgument is a usage error (2), kCorruptData a
// damaged .svc file (3), anything else a failed command (1).
int exit_code_for(const Status& status);

// Prints "PROGRAM: <status>" on stderr and returns exit_code_for(status). After SIGINT or
// SIGTERM it reports the interruption instead ("nothing was written") and returns
// 128 + the signal number. Call from the main thread once the work has stopped.
int report_failure(const char* program, const Status& status);

}  // namespace svc::command_line
