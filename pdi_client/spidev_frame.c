/* spidev_frame.h: SPI_IOC_MESSAGE transfers -> chip-select windows. */
#include "spidev_frame.h"

#include <errno.h>
#include <string.h>

enum { kBitsPerByte = 8, kSingleWire = 1 };

static const uint8_t *tx_of(const struct spi_ioc_transfer *t) {
  return (const uint8_t *)(uintptr_t)t->tx_buf;
}
static uint8_t *rx_of(const struct spi_ioc_transfer *t) { return (uint8_t *)(uintptr_t)t->rx_buf; }

/* The window ends after transfer i: the last one, or cs_change before it. */
static int ends_window(const struct spi_ioc_transfer *xfers, unsigned n, unsigned i) {
  return i + 1 == n || xfers[i].cs_change != 0;
}

static long check(const struct spi_ioc_transfer *xfers, unsigned n, size_t scratch_size) {
  size_t window = 0;
  long total = 0;
  for (unsigned i = 0; i < n; ++i) {
    const struct spi_ioc_transfer *t = &xfers[i];
    if (t->bits_per_word != 0 && t->bits_per_word != kBitsPerByte) return -EINVAL;
    if (t->tx_nbits > kSingleWire || t->rx_nbits > kSingleWire) return -EINVAL;
    window += t->len;
    total += (long)t->len;
    if (window > scratch_size) return -EMSGSIZE;
    if (ends_window(xfers, n, i)) window = 0;
  }
  return total;
}

long spidev_run_message(const struct spi_ioc_transfer *xfers, unsigned n, uint8_t *scratch, size_t scratch_size,
                        spidev_window_fn window, void *ctx) {
  long total = check(xfers, n, scratch_size);
  unsigned first = 0; /* the window's first transfer */
  size_t fill = 0;
  if (total < 0) return total;
  for (unsigned i = 0; i < n; ++i) {
    const struct spi_ioc_transfer *t = &xfers[i];
    if (t->len > 0) {
      if (tx_of(t) != NULL) {
        memcpy(scratch + fill, tx_of(t), t->len);
      } else {
        memset(scratch + fill, 0, t->len);
      }
      fill += t->len;
    }
    if (!ends_window(xfers, n, i)) continue;
    if (fill > 0) {
      size_t at = 0;
      if (window(ctx, scratch, fill) != 0) return -EIO;
      for (unsigned k = first; k <= i; ++k) {
        if (rx_of(&xfers[k]) != NULL && xfers[k].len > 0) memcpy(rx_of(&xfers[k]), scratch + at, xfers[k].len);
        at += xfers[k].len;
      }
    }
    first = i + 1;
    fill = 0;
  }
  return total;
}
