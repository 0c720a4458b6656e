/* A SOES hardware layer (soes/hal/<board>/esc_hw.c's role) for the ESC
 * that `ecat-slave --pdi-host PATH --pdi-chip direct` emulates: SOES's
 * ESC_read/ESC_write/ESC_init/ESC_reset and the interrupt-mask hooks over
 * libecat_pdi (docs/pdi-host.md). Compile it with SOES's sources and the
 * application's, instead of a board's esc_hw.c; nothing else changes.
 *
 * The socket is taken from the environment variable ECAT_PDI_SOCKET, else
 * from the application's esc_cfg_t user_arg. Without the host the firmware
 * cannot run: the HAL says why on stderr and exits with status 1, as it
 * does when the host goes away (a µC whose ESC is gone).
 *
 * ECAT_PDI_ACCESS_NS (optional, default 0): time each ESC access takes on
 * top of the round trip to the host, to give the firmware the pace of its
 * board (a LAN9252 CSR access over SPI costs tens of µs). SOES counts its
 * own process-data watchdog in main-loop passes (esc_cfg_t.watchdog_cnt),
 * so on the PC, where an access is a few µs, 150 passes can end before the
 * master's next cycle (docs/pdi-host.md). */
/* nanosleep, and glibc's BYTE_ORDER which SOES's cc.h tests: a bare
 * _POSIX_C_SOURCE would hide the latter and make etohs() swap bytes. */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE
#endif

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "ecat_pdi.h"
#include "esc.h"
#include "esc_hw.h"

#define SOES_HAL_ERROR_SIZE 200
#define SOES_HAL_EVENT_BYTES 2u /* SOES keeps the AL event's low word */

static ecat_pdi *pdi = NULL;
static struct timespec access_time = {0, 0};

static void pace(void) {
  if (access_time.tv_sec != 0 || access_time.tv_nsec != 0) nanosleep(&access_time, NULL);
}

static void hal_fail(const char *what) {
  fprintf(stderr, "soes-hal: %s: %s\n", what, pdi ? ecat_pdi_error(pdi) : "not connected");
  exit(1);
}

/* As an ET1100 returns the AL event request in every access's address
 * phase, SOES expects ESCvar.ALevent fresh after each access. */
static void refresh_alevent(void) {
  uint16_t event = 0;
  if (ecat_pdi_esc_read(pdi, ESCREG_ALEVENT, &event, SOES_HAL_EVENT_BYTES) != 0) hal_fail("AL event read");
  ESCvar.ALevent = etohs(event);
}

void ESC_read(uint16_t address, void *buf, uint16_t len) {
  if (ecat_pdi_esc_read(pdi, address, buf, len) != 0) hal_fail("ESC_read");
  refresh_alevent();
  pace();
}

void ESC_write(uint16_t address, void *buf, uint16_t len) {
  if (ecat_pdi_esc_write(pdi, address, buf, len) != 0) hal_fail("ESC_write");
  refresh_alevent();
  pace();
}

/* The emulated ESC has no reset line a firmware could pull. */
void ESC_reset(void) {}

void ESC_init(const esc_cfg_t *config) {
  char error[SOES_HAL_ERROR_SIZE];
  const char *path = getenv("ECAT_PDI_SOCKET");
  const char *pace_ns = getenv("ECAT_PDI_ACCESS_NS");
  if (pace_ns && *pace_ns) {
    long ns = strtol(pace_ns, NULL, 10);
    if (ns < 0 || ns > 999999999L) {
      fprintf(stderr, "soes-hal: ECAT_PDI_ACCESS_NS=%s: 0..999999999 ns expected\n", pace_ns);
      exit(1);
    }
    access_time.tv_nsec = ns;
  }
  if (!path || !*path) path = config ? (const char *)config->user_arg : NULL;
  if (!path) {
    fprintf(stderr, "soes-hal: set ECAT_PDI_SOCKET to the path of ecat-slave --pdi-host\n");
    exit(1);
  }
  pdi = ecat_pdi_connect(path, error, sizeof error);
  if (!pdi) {
    fprintf(stderr, "soes-hal: %s\n", error);
    exit(1);
  }
  if (ecat_pdi_chip(pdi) != ECAT_PDI_CHIP_DIRECT) {
    fprintf(stderr, "soes-hal: %s offers an SPI PDI; this HAL needs --pdi-chip direct\n", path);
    exit(1);
  }
}

void ESC_interrupt_enable(uint32_t mask) {
  uint32_t now = 0;
  if (ecat_pdi_esc_read(pdi, ESCREG_ALEVENTMASK, &now, sizeof now) != 0) hal_fail("AL event mask read");
  now = htoel(etohl(now) | mask);
  if (ecat_pdi_esc_write(pdi, ESCREG_ALEVENTMASK, &now, sizeof now) != 0) hal_fail("AL event mask write");
}

void ESC_interrupt_disable(uint32_t mask) {
  uint32_t now = 0;
  if (ecat_pdi_esc_read(pdi, ESCREG_ALEVENTMASK, &now, sizeof now) != 0) hal_fail("AL event mask read");
  now = htoel(etohl(now) & ~mask);
  if (ecat_pdi_esc_write(pdi, ESCREG_ALEVENTMASK, &now, sizeof now) != 0) hal_fail("AL event mask write");
}

ecat_pdi *ESC_pdi(void) { return pdi; }

int ESC_wait_interrupt(int timeout_ms) {
  int r = ecat_pdi_wait_irq(pdi, timeout_ms, NULL);
  if (r < 0) hal_fail("wait for the interrupt");
  return r;
}
