/* Chip-select framing of a Linux spidev SPI_IOC_MESSAGE(N) for the spidev
 * shim (spidev_shim.c, docs/firmware-in-the-loop.md): the transfers of one
 * message are cut into chip-select windows, each window one SPI transaction
 * of libecat_pdi. No I/O here, so the framing is tested without a process
 * (tests/pdi_host/spidev_shim_logic_test.cpp). C99. */
#ifndef ECAT_SPIDEV_FRAME_H
#define ECAT_SPIDEV_FRAME_H

#include <linux/spi/spidev.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* One chip-select window: `len` MOSI bytes in `buf`, replaced by as many
 * MISO bytes. 0 on success, -1 when the chip is gone. */
typedef int (*spidev_window_fn)(void *ctx, uint8_t *buf, size_t len);

/* Runs the `n` transfers of one message. A message is one window (chip
 * select low from its first clock to its last) except where a transfer that
 * is not the last has cs_change set: chip select rises after it and the next
 * transfer opens a new window. cs_change on the last transfer (spidev: keep
 * chip select low into the next message) cannot be honoured - the host's
 * transaction ends with the message - and the window ends there too.
 * A transfer's tx_buf 0 clocks out zeros; rx_buf 0 drops what came in.
 * Checks before anything is sent: bits_per_word 0 or 8, tx_nbits/rx_nbits
 * 0 or 1 (single-wire), a window of at most `scratch_size` bytes.
 * Returns the total length of the message (what spidev's ioctl returns), or
 * -EINVAL / -EMSGSIZE for a message refused, -EIO when `window` failed. */
long spidev_run_message(const struct spi_ioc_transfer *xfers, unsigned n, uint8_t *scratch, size_t scratch_size,
                        spidev_window_fn window, void *ctx);

#ifdef __cplusplus
}
#endif

#endif /* ECAT_SPIDEV_FRAME_H */
