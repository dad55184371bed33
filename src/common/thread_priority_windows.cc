// SPDX-License-Identifier: BSD-2-Clause
// lower_current_thread_priority on Windows.
#include <windows.h>

#include "common/thread_priority.h"

namespace svc {

void lower_current_thread_priority() { (void)SetThreadPriority(GetCurrentThread(), THREAD_PRIORITY_BELOW_NORMAL); }

}  // namespace svc
