/* libecat_pdi: a firmware process's side of `ecat-slave --pdi-host`
 * (docs/pdi-host.md). C99, POSIX; no C++ needed in the firmware's build.
 * One handle per connection; calls on a handle are not thread-safe (an
 * interrupt thread and a main loop must share it under a lock).
 *
 * Functions returning int give 0 on success and -1 on failure (then
 * ecat_pdi_error() says why; a failed handle is closed to further use
 * except ecat_pdi_close()). */
#ifndef ECAT_PDI_H
#define ECAT_PDI_H

#include <stddef.h>
#include <stdint.h>

#include "ecat_pdi_protocol.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ecat_pdi ecat_pdi;

/* The firmware's interrupt input (the host's LINES message). */
typedef struct ecat_pdi_lines {
  uint32_t event_request; /* AL event request 0x0220 */
  uint32_t event_mask;    /* AL event mask 0x0204 */
  uint8_t irq;            /* 1: the IRQ line is asserted */
  uint8_t sync;           /* ECAT_PDI_SYNC0 / ECAT_PDI_SYNC1 pulses seen */
  uint64_t time_ns;       /* the ESC's local time when the host sent it */
} ecat_pdi_lines;

/* Connects to the host's socket and reads its HELLO. NULL on failure, with
 * the reason in `error` (when not NULL, `error_size` bytes). */
ecat_pdi *ecat_pdi_connect(const char *path, char *error, size_t error_size);
void ecat_pdi_close(ecat_pdi *pdi);
/* Why the last call failed ("" when none did). */
const char *ecat_pdi_error(const ecat_pdi *pdi);
/* The PDI the host offers: ECAT_PDI_CHIP_DIRECT, _LAN9252 or _ET1100_SPI. */
int ecat_pdi_chip(const ecat_pdi *pdi);
/* The connection's descriptor, readable when the host sent something (to
 * wait on it with other descriptors; then call ecat_pdi_wait_irq(pdi, 0)). */
int ecat_pdi_fd(const ecat_pdi *pdi);

/* ESC memory, direct PDI: `len` bytes at `address` (address + len <= 0x10000;
 * a write at most 65533 bytes). */
int ecat_pdi_esc_read(ecat_pdi *pdi, uint16_t address, void *buf, uint16_t len);
int ecat_pdi_esc_write(ecat_pdi *pdi, uint16_t address, const void *buf, uint16_t len);
/* One SPI transaction, lan9252 / et1100-spi PDI: `len` bytes out on MOSI,
 * as many in from MISO into `rx` (which may be `tx`). */
int ecat_pdi_spi_transfer(ecat_pdi *pdi, const void *tx, void *rx, uint16_t len);

/* Waits up to `timeout_ms` (0: only what has arrived; -1: forever) for the
 * interrupt: returns 1 when the IRQ line is asserted or a SYNC pulse came
 * since the last call (then `lines`, when not NULL, holds the latest lines,
 * its `sync` the pulses since the last call), 0 on timeout, -1 on failure. */
int ecat_pdi_wait_irq(ecat_pdi *pdi, int timeout_ms, ecat_pdi_lines *lines);
/* The lines as the host sees them now (asks it). */
int ecat_pdi_lines_now(ecat_pdi *pdi, ecat_pdi_lines *lines);
/* The ESC's local time in ns. */
int ecat_pdi_read_time(ecat_pdi *pdi, uint64_t *ns);

#ifdef __cplusplus
}
#endif

#endif /* ECAT_PDI_H */
