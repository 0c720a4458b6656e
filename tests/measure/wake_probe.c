/* A cyclictest-style probe (docs/e2e.md "Does the VM stall everything?"):
 * one thread, SCHED_FIFO where allowed, memory locked, sleeps to absolute
 * 1 ms deadlines (clock_nanosleep TIMER_ABSTIME on CLOCK_MONOTONIC) for
 * SECONDS and records how late each wake-up was: a histogram, the maximum,
 * and the wall-clock second of every wake-up later than 1 ms, so stalls can
 * be matched against other processes' logs. It tells whether the host stalls
 * every process of the VM (then it sees the same stalls as ecat-master) or
 * only some. Not built by CMake: a measurement tool,
 *   cc -O2 -o /tmp/wake_probe tests/measure/wake_probe.c
 *   /tmp/wake_probe SECONDS [PRIORITY]        (PRIORITY 0: SCHED_OTHER)
 */
#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

#define NS_PER_S 1000000000LL
#define NS_PER_US 1000LL
#define PERIOD_NS 1000000LL
#define BUCKETS 10
#define MAX_STALLS 64

static const long long edges_us[BUCKETS - 1] = {10, 50, 100, 250, 500, 1000, 2000, 5000, 20000};

static long long ns_of(const struct timespec *t) { return (long long)t->tv_sec * NS_PER_S + t->tv_nsec; }

int main(int argc, char **argv) {
  const long long seconds = argc > 1 ? atoll(argv[1]) : 60;
  const int priority = argc > 2 ? atoi(argv[2]) : 80;
  const char *policy = "SCHED_OTHER";
  if (priority > 0) {
    struct sched_param sp = {.sched_priority = priority};
    int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
    if (rc == 0) policy = "SCHED_FIFO";
    else fprintf(stderr, "wake_probe: SCHED_FIFO %d refused: %s\n", priority, strerror(rc));
    if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) fprintf(stderr, "wake_probe: mlockall: %s\n", strerror(errno));
  }
  long long hist[BUCKETS] = {0};
  long long stall_at[MAX_STALLS], stall_ns[MAX_STALLS];
  int stalls = 0;
  long long max_ns = 0, total_ns = 0, n = 0, over_1ms_ns = 0;
  struct timespec next;
  clock_gettime(CLOCK_MONOTONIC, &next);
  long long t = ns_of(&next);
  const long long end = t + seconds * NS_PER_S;
  while (t < end) {
    t += PERIOD_NS;
    next.tv_sec = t / NS_PER_S;
    next.tv_nsec = t % NS_PER_S;
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL) == EINTR) {
    }
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    const long long late = ns_of(&now) - t;
    int b = 0;
    while (b < BUCKETS - 1 && late >= edges_us[b] * NS_PER_US) ++b;
    ++hist[b];
    ++n;
    total_ns += late;
    if (late > max_ns) max_ns = late;
    if (late >= PERIOD_NS) {
      over_1ms_ns += late;
      if (stalls < MAX_STALLS) {
        struct timespec wall;
        clock_gettime(CLOCK_REALTIME, &wall);
        stall_at[stalls] = ns_of(&wall);
        stall_ns[stalls] = late;
      }
      ++stalls;
    }
    /* A stall of several periods: resume at the next period still ahead. */
    while (t + PERIOD_NS <= ns_of(&now)) t += PERIOD_NS;
  }
  printf("wake_probe %s prio %d: %lld wake-ups, mean %.1f us, max %.1f us, %d later than 1 ms (%.1f ms in all)\n",
         policy, priority, n, n ? (double)total_ns / (double)n / 1e3 : 0.0, (double)max_ns / 1e3, stalls,
         (double)over_1ms_ns / 1e6);
  printf("late <10us %lld <50us %lld <100us %lld <250us %lld <500us %lld <1ms %lld <2ms %lld <5ms %lld <20ms %lld >=20ms %lld\n",
         hist[0], hist[1], hist[2], hist[3], hist[4], hist[5], hist[6], hist[7], hist[8], hist[9]);
  for (int i = 0; i < stalls && i < MAX_STALLS; ++i) {
    const time_t s = (time_t)(stall_at[i] / NS_PER_S);
    struct tm tm;
    gmtime_r(&s, &tm);
    printf("stall %02d:%02d:%02d.%03lld UTC %.1f ms\n", tm.tm_hour, tm.tm_min, tm.tm_sec,
           (stall_at[i] % NS_PER_S) / 1000000LL, (double)stall_ns[i] / 1e6);
  }
  return 0;
}
