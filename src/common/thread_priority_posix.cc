// SPDX-License-Identifier: BSD-2-Clause
// lower_current_thread_priority on Linux: the nice value, which Linux keeps per thread.
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "common/thread_priority.h"

namespace svc {

void lower_current_thread_priority() {
  (void)setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10);
}

}  // namespace svc
