// SPDX-License-Identifier: BSD-2-Clause
// SIGINT and SIGTERM as a request to stop: the work in progress is cancelled through its
// progress callback, what it wrote is removed, and the program exits 128 + the signal
// number (130 for Ctrl-C, 143 for SIGTERM), as shells report a killed command.
#pragma once

namespace svc::command_line {

// Installs the handlers. The first signal only records the request; a second one ends
// the program at once (the default action), for a command that does not reach a point
// where it can stop.
void stop_on_interrupt();

// Whether a signal asked the program to stop. Async-signal-safe to read; any thread.
bool interrupted();

// 128 + the signal that asked to stop (0 when none did).
int interrupted_exit_code();

// "SIGINT" or "SIGTERM" (empty when none).
const char* interrupting_signal_name();

}  // namespace svc::command_line
