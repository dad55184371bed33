// SPDX-License-Identifier: BSD-2-Clause
// Background threads that yield to the threads a caller is waiting on.
#pragma once

namespace svc {

// Lowers the calling thread's scheduling priority a little (thread_priority_posix.cc,
// thread_priority_windows.cc). Best effort: a refusal leaves the priority as it was.
void lower_current_thread_priority();

}  // namespace svc
