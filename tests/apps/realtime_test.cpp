// ecat-slave --rt-priority locks memory as root, then drops to an
// unprivileged user: the process must still be able to allocate (issue 19).
#include "apps/ecat-slave/realtime.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "transport/raw_socket_transport.hpp"

namespace ecat::app {
namespace {

constexpr std::size_t kDefaultMemlock = 8u << 20;  // Debian's default RLIMIT_MEMLOCK
constexpr std::size_t kGrowth = 64u << 20;         // heap growth after the drop, past the limit
constexpr uid_t kNobody = 65534;

enum ChildExit : int { kAllocated = 0, kLockFailed = 2, kDropFailed = 3, kAllocationFailed = 4, kSetUpFailed = 5 };

// Runs `lock_first ? lock, drop : drop, lock`, then grows the heap, in a
// child so the test process keeps its own limits and privileges.
int run_child(bool lock_first) {
  const pid_t pid = fork();
  if (pid == 0) {
    const rlimit debian{kDefaultMemlock, kDefaultMemlock};
    if (setrlimit(RLIMIT_MEMLOCK, &debian) != 0) _exit(kSetUpFailed);
    if (lock_first && !lock_memory()) _exit(kLockFailed);
    if (!transport::drop_privileges(kNobody, kNobody)) _exit(kDropFailed);
    if (!lock_first) (void)lock_memory();  // may lock only what is mapped, or nothing: either is fine
    void* p = std::malloc(kGrowth);
    if (p == nullptr) _exit(kAllocationFailed);
    std::memset(p, 0x5A, kGrowth);
    std::free(p);
    _exit(kAllocated);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

TEST(MemoryLock, AllocationsPastTheLimitStillWorkAfterDroppingPrivileges) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to drop privileges";
  EXPECT_EQ(run_child(true), kAllocated);
}

TEST(MemoryLock, AnUnprivilegedProcessStillAllocates) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to become an unprivileged user";
  EXPECT_EQ(run_child(false), kAllocated);
}

}  // namespace
}  // namespace ecat::app
