// Real-time set-up for live runs: SCHED_FIFO priority, locked memory, CPU
// affinity. Each returns a message on failure; the caller decides whether
// that is fatal (it is when the user asked for it explicitly).
#pragma once

#include <string>

#include "common/expected.hpp"

namespace ecat::app {

Expected<void, std::string> set_realtime_priority(int priority);
// How much lock_memory() could lock: everything, now and later (the memlock
// limit was raised), or only the pages mapped now (it could not be).
enum class MemoryLock { CurrentAndFuture, CurrentOnly };
Expected<MemoryLock, std::string> lock_memory();
Expected<void, std::string> pin_to_cpu(int cpu);

}  // namespace ecat::app
