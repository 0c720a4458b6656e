#include "apps/ecat-slave/realtime.hpp"

#include <sched.h>
#include <sys/mman.h>

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

Expected<void, std::string> lock_memory() {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    return fail(fmt::format("cannot lock memory: {}", std::strerror(errno)));
  }
  return {};
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
