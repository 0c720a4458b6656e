/* The cost of one cycle of a SOES application through the PDI host (issue
 * 28 item 4), for scripts/bench-pdi. Linked into an unmodified SOES sample
 * with -Wl,--wrap=ecat_slv,--wrap=ESC_read,--wrap=ESC_write: every call of
 * ecat_slv() from the sample's main loop is timed (CLOCK_MONOTONIC), and the
 * HAL's ESC accesses in it counted. Passes are recorded while SOES is in Op
 * (ESCvar.ALstatus); after SOES_CYCLE_PASSES of them (default 20000) one
 * line goes to stderr and the firmware runs on untimed:
 *   soes-cycle: passes N median-us M p99-us P max-us X accesses-per-pass A
 * C99 against SOES's headers (the sample's include path); not built by the
 * project's CMake (SOES is not in the repository). */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "esc.h"

void __real_ecat_slv(void);
void __real_ESC_read(uint16_t address, void *buf, uint16_t len);
void __real_ESC_write(uint16_t address, void *buf, uint16_t len);

static uint64_t accesses;
static int64_t *passes;
static long wanted = -1;
static long recorded;
static uint64_t accesses_recorded;

static int64_t mono_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static int by_value(const void *a, const void *b) {
  const int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

static void report(void) {
  qsort(passes, (size_t)recorded, sizeof *passes, by_value);
  long p99 = recorded * 99 / 100;
  if (p99 >= recorded) p99 = recorded - 1;
  fprintf(stderr, "soes-cycle: passes %ld median-us %.1f p99-us %.1f max-us %.1f accesses-per-pass %.2f\n", recorded,
          (double)passes[recorded / 2] / 1e3, (double)passes[p99] / 1e3, (double)passes[recorded - 1] / 1e3,
          (double)accesses_recorded / (double)recorded);
  fflush(stderr);
}

void __wrap_ESC_read(uint16_t address, void *buf, uint16_t len) {
  ++accesses;
  __real_ESC_read(address, buf, len);
}

void __wrap_ESC_write(uint16_t address, void *buf, uint16_t len) {
  ++accesses;
  __real_ESC_write(address, buf, len);
}

void __wrap_ecat_slv(void) {
  if (wanted < 0) {
    const char *n = getenv("SOES_CYCLE_PASSES");
    wanted = n ? atol(n) : 20000;
    if (wanted <= 0) wanted = 20000;
    passes = malloc((size_t)wanted * sizeof *passes);
    if (passes == NULL) wanted = 0;
  }
  const uint64_t a0 = accesses;
  const int64_t t0 = mono_ns();
  __real_ecat_slv();
  const int64_t t1 = mono_ns();
  if (recorded < wanted && (ESCvar.ALstatus & 0x0F) == ESCop) {
    passes[recorded++] = t1 - t0;
    accesses_recorded += accesses - a0;
    if (recorded == wanted) report();
  }
}
