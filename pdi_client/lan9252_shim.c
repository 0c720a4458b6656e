/* LD_PRELOAD shim for firmware built for a LAN9252 behind a Linux character
 * device (issue 28 item 2; docs/pdi-host.md "The LAN9252 device shim").
 *
 * SOES's Linux LAN9252 HAL (soes/hal/linux-lan9252/esc_hw.c) talks to the
 * chip through a device file (/dev/lan9252 by default):
 *   - open(path, O_RDWR);
 *   - a register read: lseek(fd, address, SEEK_SET) + read(fd, buf, n), the
 *     n bytes the chip returns for a serial read (0x03) at that address;
 *   - a write: write(fd, [0x02, address high, address low, data...]), the
 *     MOSI bytes of one SPI transaction as they are.
 * This shim intercepts open of that path ($ECAT_LAN9252_DEVICE, default
 * /dev/lan9252) and the lseek/read/write/close on its descriptor, and turns
 * them into SPI transactions of libecat_pdi against `ecat-slave --pdi-host
 * SOCKET --pdi-chip lan9252` ($ECAT_PDI_SOCKET). Every other file goes to
 * the C library untouched. The descriptor returned is a real one (of
 * /dev/null), so it never collides with the firmware's other files.
 * One device at a time; not thread-safe (as libecat_pdi).
 *
 * C99 with POSIX and dlsym(RTLD_NEXT) (a GNU extension, hence _GNU_SOURCE). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

#include "ecat_pdi.h"
#include "ecat_pdi_protocol.h"

enum {
  kSerialRead = 0x03,    /* LAN9252 SPI "serial read": command, address high, low, data */
  kHeaderBytes = 3,
  kMaxTransfer = 65535   /* one SPI message of the protocol */
};

static const char kDefaultDevice[] = "/dev/lan9252";

static ecat_pdi *shim_pdi;
static int shim_fd = -1;
static off_t shim_pos;
static uint8_t shim_buf[kMaxTransfer];

typedef int (*open_fn)(const char *, int, ...);
typedef off_t (*lseek_fn)(int, off_t, int);
typedef ssize_t (*read_fn)(int, void *, size_t);
typedef ssize_t (*write_fn)(int, const void *, size_t);
typedef int (*close_fn)(int);

/* The C library's own function `name` into the function pointer at `slot`
 * (dlsym returns an object pointer; POSIX guarantees its bits are the
 * function's address - copied, as ISO C has no conversion between them). */
static void next(void *slot, size_t size, const char *name) {
  void *f = dlsym(RTLD_NEXT, name);
  if (f == NULL || size != sizeof f) {
    fprintf(stderr, "ecat lan9252 shim: %s not found in the C library\n", name);
    abort();
  }
  memcpy(slot, &f, sizeof f);
}

static const char *device_path(void) {
  const char *p = getenv("ECAT_LAN9252_DEVICE");
  return p != NULL && p[0] != '\0' ? p : kDefaultDevice;
}

/* The device: connect to the host; the descriptor is one of /dev/null. */
static int open_device(open_fn real_open) {
  if (shim_fd >= 0) {
    errno = EBUSY;
    return -1;
  }
  const char *sock = getenv("ECAT_PDI_SOCKET");
  if (sock == NULL || sock[0] == '\0') {
    fprintf(stderr, "ecat lan9252 shim: ECAT_PDI_SOCKET is not set (the path of ecat-slave --pdi-host)\n");
    errno = ENODEV;
    return -1;
  }
  char err[256];
  ecat_pdi *p = ecat_pdi_connect(sock, err, sizeof err);
  if (p == NULL) {
    fprintf(stderr, "ecat lan9252 shim: %s\n", err);
    errno = ENODEV;
    return -1;
  }
  if (ecat_pdi_chip(p) != (int)ECAT_PDI_CHIP_LAN9252) {
    fprintf(stderr, "ecat lan9252 shim: the host does not offer a LAN9252 (ecat-slave --pdi-chip lan9252)\n");
    ecat_pdi_close(p);
    errno = ENODEV;
    return -1;
  }
  int fd = real_open("/dev/null", O_RDWR);
  if (fd < 0) {
    ecat_pdi_close(p);
    return -1;
  }
  shim_pdi = p;
  shim_fd = fd;
  shim_pos = 0;
  return fd;
}

/* The host went away or refused a transaction: the chip is gone. */
static void device_lost(void) {
  fprintf(stderr, "ecat lan9252 shim: %s\n", ecat_pdi_error(shim_pdi));
  exit(1);
}

static int open_common(const char *name, const char *path, int flags, va_list ap) {
  open_fn real;
  next(&real, sizeof real, name);
  if (path != NULL && strcmp(path, device_path()) == 0) return open_device(real);
  if ((flags & O_CREAT) != 0) return real(path, flags, va_arg(ap, int));
  return real(path, flags);
}

int open(const char *path, int flags, ...) {
  va_list ap;
  va_start(ap, flags);
  int r = open_common("open", path, flags, ap);
  va_end(ap);
  return r;
}

int open64(const char *path, int flags, ...) {
  va_list ap;
  va_start(ap, flags);
  int r = open_common("open64", path, flags, ap);
  va_end(ap);
  return r;
}

static off_t seek_device(off_t offset, int whence) {
  off_t to;
  if (whence == SEEK_SET) {
    to = offset;
  } else if (whence == SEEK_CUR) {
    to = shim_pos + offset;
  } else {
    errno = EINVAL;
    return -1;
  }
  if (to < 0 || to > 0xFFFF) {  /* the LAN9252's 16-bit SPI address */
    errno = EINVAL;
    return -1;
  }
  shim_pos = to;
  return to;
}

off_t lseek(int fd, off_t offset, int whence) {
  static lseek_fn real;
  if (fd >= 0 && fd == shim_fd) return seek_device(offset, whence);
  if (real == NULL) next(&real, sizeof real, "lseek");
  return real(fd, offset, whence);
}

off_t lseek64(int fd, off_t offset, int whence) {
  static lseek_fn real;
  if (fd >= 0 && fd == shim_fd) return seek_device(offset, whence);
  if (real == NULL) next(&real, sizeof real, "lseek64");
  return real(fd, offset, whence);
}

/* A serial read at the position: [0x03, high, low] then n clocks of data. */
ssize_t read(int fd, void *buf, size_t n) {
  static read_fn real;  /* libecat_pdi's own socket reads come here too */
  if (fd < 0 || fd != shim_fd) {
    if (real == NULL) next(&real, sizeof real, "read");
    return real(fd, buf, n);
  }
  if (n == 0) return 0;
  if (n > kMaxTransfer - kHeaderBytes) n = kMaxTransfer - kHeaderBytes;
  memset(shim_buf, 0, n + kHeaderBytes);
  shim_buf[0] = kSerialRead;
  shim_buf[1] = (uint8_t)((uint32_t)shim_pos >> 8);
  shim_buf[2] = (uint8_t)shim_pos;
  if (ecat_pdi_spi_transfer(shim_pdi, shim_buf, shim_buf, (uint16_t)(n + kHeaderBytes)) != 0) device_lost();
  memcpy(buf, shim_buf + kHeaderBytes, n);
  return (ssize_t)n;
}

/* The bytes written are one SPI transaction's MOSI bytes, as they are. */
ssize_t write(int fd, const void *buf, size_t n) {
  static write_fn real;
  if (fd < 0 || fd != shim_fd) {
    if (real == NULL) next(&real, sizeof real, "write");
    return real(fd, buf, n);
  }
  if (n == 0) return 0;
  if (n > kMaxTransfer) {
    errno = EINVAL;
    return -1;
  }
  memcpy(shim_buf, buf, n);
  if (ecat_pdi_spi_transfer(shim_pdi, shim_buf, shim_buf, (uint16_t)n) != 0) device_lost();
  return (ssize_t)n;
}

int close(int fd) {
  static close_fn real;
  if (real == NULL) next(&real, sizeof real, "close");
  if (fd >= 0 && fd == shim_fd) {
    ecat_pdi_close(shim_pdi);
    shim_pdi = NULL;
    shim_fd = -1;
  }
  return real(fd);
}
