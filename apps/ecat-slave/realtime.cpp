#include "apps/ecat-slave/realtime.hpp"

#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

namespace ecat::app {

Expected<void, std::string> set_realtime_priority(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  if (sched_setscheduler(0, SCHED_FIFO, &param) != 0) {
    return fail(fmt::format("cannot set SCHED_FIFO priority {}: {}", priority, std::strerror(errno)));
  }
  return {};
}

// With MCL_FUTURE every later mapping is locked and counts against
// RLIMIT_MEMLOCK (mlockall(2)). Root is exempt (CAP_IPC_LOCK), but
// ecat-slave drops to an unprivileged user once its socket is open, and from
// then on heap growth past the limit (8 MiB by default) failed: issue 19 saw
// the SVG plot cut off. So the limit is raised first while root may (rlimits
// survive setuid); a process that cannot raise it locks only what it has now,
// and its later allocations are simply not locked.
Expected<MemoryLock, std::string> lock_memory() {
  const rlimit unlimited{RLIM_INFINITY, RLIM_INFINITY};
  if (setrlimit(RLIMIT_MEMLOCK, &unlimited) == 0) {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
      return fail(fmt::format("cannot lock memory: {}", std::strerror(errno)));
    }
    return MemoryLock::CurrentAndFuture;
  }
  if (mlockall(MCL_CURRENT) != 0) {
    rlimit limit{};
    (void)getrlimit(RLIMIT_MEMLOCK, &limit);
    return fail(fmt::format("cannot lock memory within RLIMIT_MEMLOCK ({} bytes): {}", limit.rlim_cur,
                            std::strerror(errno)));
  }
  return MemoryLock::CurrentOnly;
}

Expected<void, std::string> pin_to_cpu(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  if (sched_setaffinity(0, sizeof(set), &set) != 0) {
    return fail(fmt::format("cannot pin to CPU {}: {}", cpu, std::strerror(errno)));
  }
  return {};
}

}  // namespace ecat::app
