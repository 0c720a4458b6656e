/* libecat_pdi (ecat_pdi.h): the protocol of ecat_pdi_protocol.h over a
 * blocking Unix stream socket. Requests are answered in order; LINES
 * notifications that arrive between replies are kept as the latest lines. */
#define _POSIX_C_SOURCE 200809L

#include "ecat_pdi.h"

#include <errno.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#define ECAT_PDI_ERROR_SIZE 160
#define ECAT_PDI_HELLO_SIZE 4u
#define ECAT_PDI_TIME_SIZE 8u
#define ECAT_PDI_WRITE_MAX (ECAT_PDI_MAX_PAYLOAD - 2u)
#define ECAT_PDI_ADDRESS_SPACE 0x10000ul

struct ecat_pdi {
  int fd;
  int chip;
  int failed;
  ecat_pdi_lines lines;  /* latest lines received */
  uint8_t sync_pending;  /* SYNC pulses not yet given to wait_irq */
  char error[ECAT_PDI_ERROR_SIZE];
  uint8_t scratch[ECAT_PDI_MAX_PAYLOAD]; /* payloads read and discarded or copied */
};

static uint16_t get16(const uint8_t *p) { return (uint16_t)(p[0] | (p[1] << 8)); }
static uint32_t get32(const uint8_t *p) { return (uint32_t)get16(p) | ((uint32_t)get16(p + 2) << 16); }
static uint64_t get64(const uint8_t *p) { return (uint64_t)get32(p) | ((uint64_t)get32(p + 4) << 32); }
static void put16(uint8_t *p, uint16_t v) {
  p[0] = (uint8_t)(v & 0xFFu);
  p[1] = (uint8_t)(v >> 8);
}

static int fail(ecat_pdi *pdi, const char *format, ...) {
  va_list args;
  va_start(args, format);
  vsnprintf(pdi->error, sizeof pdi->error, format, args);
  va_end(args);
  pdi->failed = 1;
  return -1;
}

static int send_all(ecat_pdi *pdi, const uint8_t *data, size_t size) {
  while (size > 0) {
    ssize_t n = send(pdi->fd, data, size, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return fail(pdi, "send: %s", n < 0 ? strerror(errno) : "connection closed");
    data += n;
    size -= (size_t)n;
  }
  return 0;
}

static int recv_all(ecat_pdi *pdi, uint8_t *data, size_t size) {
  while (size > 0) {
    ssize_t n = recv(pdi->fd, data, size, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return fail(pdi, "recv: %s", strerror(errno));
    if (n == 0) return fail(pdi, "the host closed the connection");
    data += n;
    size -= (size_t)n;
  }
  return 0;
}

static int send_request(ecat_pdi *pdi, uint8_t type, const uint8_t *head, size_t head_size, const void *data,
                        size_t data_size) {
  uint8_t header[ECAT_PDI_HEADER_SIZE + 4];
  size_t payload = head_size + data_size;
  if (pdi->failed) return -1;
  header[0] = type;
  header[1] = 0;
  put16(header + 2, (uint16_t)payload);
  if (head_size) memcpy(header + ECAT_PDI_HEADER_SIZE, head, head_size);
  if (send_all(pdi, header, ECAT_PDI_HEADER_SIZE + head_size) != 0) return -1;
  return data_size ? send_all(pdi, (const uint8_t *)data, data_size) : 0;
}

static void take_lines(ecat_pdi *pdi, const uint8_t *p) {
  pdi->lines.event_request = get32(p);
  pdi->lines.event_mask = get32(p + 4);
  pdi->lines.irq = p[8];
  pdi->lines.sync = p[9];
  pdi->lines.time_ns = get64(p + 12);
  pdi->sync_pending = (uint8_t)(pdi->sync_pending | p[9]);
}

/* Reads one message. A notification is taken in and 0 returned; a reply of
 * `want` type with `size` payload bytes (`size` < 0: any) goes to `out`
 * and 1 is returned. -1 on failure. */
static int read_message(ecat_pdi *pdi, uint8_t want, long size, void *out) {
  uint8_t header[ECAT_PDI_HEADER_SIZE];
  uint16_t length;
  if (recv_all(pdi, header, sizeof header) != 0) return -1;
  length = get16(header + 2);
  if (header[0] == ECAT_PDI_MSG_NOTIFY) {
    if (length != ECAT_PDI_LINES_SIZE) return fail(pdi, "notification of %u bytes", (unsigned)length);
    if (recv_all(pdi, pdi->scratch, length) != 0) return -1;
    take_lines(pdi, pdi->scratch);
    return 0;
  }
  if (header[0] != want || header[1] != 0 || (size >= 0 && length != (unsigned long)size)) {
    return fail(pdi, "unexpected message 0x%02X of %u bytes (waited for 0x%02X)", header[0], (unsigned)length, want);
  }
  if (recv_all(pdi, out ? (uint8_t *)out : pdi->scratch, length) != 0) return -1;
  return 1;
}

static int await_reply(ecat_pdi *pdi, uint8_t request, long size, void *out) {
  int r;
  while ((r = read_message(pdi, (uint8_t)(request | ECAT_PDI_REPLY), size, out)) == 0) {
  }
  return r < 0 ? -1 : 0;
}

ecat_pdi *ecat_pdi_connect(const char *path, char *error, size_t error_size) {
  struct sockaddr_un addr;
  uint8_t hello[ECAT_PDI_HELLO_SIZE];
  ecat_pdi *pdi = (ecat_pdi *)calloc(1, sizeof *pdi);
  if (!pdi) {
    if (error) snprintf(error, error_size, "out of memory");
    return NULL;
  }
  pdi->fd = -1;
  memset(&addr, 0, sizeof addr);
  addr.sun_family = AF_UNIX;
  if (!path || strlen(path) == 0 || strlen(path) >= sizeof addr.sun_path) {
    fail(pdi, "socket path of 1..%u bytes needed", (unsigned)(sizeof addr.sun_path - 1));
  } else {
    memcpy(addr.sun_path, path, strlen(path));
    pdi->fd = socket(AF_UNIX, SOCK_STREAM, 0);
    if (pdi->fd < 0 || connect(pdi->fd, (const struct sockaddr *)&addr, sizeof addr) != 0) {
      fail(pdi, "%s: %s", path, strerror(errno));
    } else if (await_reply(pdi, (uint8_t)(ECAT_PDI_MSG_HELLO & ~ECAT_PDI_REPLY), ECAT_PDI_HELLO_SIZE, hello) == 0) {
      if (get16(hello) != ECAT_PDI_PROTOCOL_VERSION) {
        fail(pdi, "%s: protocol version %u, this library speaks %u", path, (unsigned)get16(hello),
             ECAT_PDI_PROTOCOL_VERSION);
      }
      pdi->chip = hello[2];
    }
  }
  if (pdi->failed) {
    if (error) snprintf(error, error_size, "%s", pdi->error);
    ecat_pdi_close(pdi);
    return NULL;
  }
  return pdi;
}

void ecat_pdi_close(ecat_pdi *pdi) {
  if (!pdi) return;
  if (pdi->fd >= 0) close(pdi->fd);
  free(pdi);
}

const char *ecat_pdi_error(const ecat_pdi *pdi) { return pdi ? pdi->error : "no handle"; }
int ecat_pdi_chip(const ecat_pdi *pdi) { return pdi->chip; }
int ecat_pdi_fd(const ecat_pdi *pdi) { return pdi->fd; }

int ecat_pdi_esc_read(ecat_pdi *pdi, uint16_t address, void *buf, uint16_t len) {
  uint8_t head[4];
  if (len == 0) return 0;
  if ((unsigned long)address + len > ECAT_PDI_ADDRESS_SPACE) {
    return fail(pdi, "read of %u bytes at 0x%04X: past 0xFFFF", (unsigned)len, (unsigned)address);
  }
  put16(head, address);
  put16(head + 2, len);
  if (send_request(pdi, ECAT_PDI_MSG_READ, head, sizeof head, NULL, 0) != 0) return -1;
  return await_reply(pdi, ECAT_PDI_MSG_READ, len, buf);
}

int ecat_pdi_esc_write(ecat_pdi *pdi, uint16_t address, const void *buf, uint16_t len) {
  uint8_t head[2];
  if (len == 0) return 0;
  if (len > ECAT_PDI_WRITE_MAX || (unsigned long)address + len > ECAT_PDI_ADDRESS_SPACE) {
    return fail(pdi, "write of %u bytes at 0x%04X: too long or past 0xFFFF", (unsigned)len, (unsigned)address);
  }
  put16(head, address);
  if (send_request(pdi, ECAT_PDI_MSG_WRITE, head, sizeof head, buf, len) != 0) return -1;
  return await_reply(pdi, ECAT_PDI_MSG_WRITE, 0, NULL);
}

int ecat_pdi_spi_transfer(ecat_pdi *pdi, const void *tx, void *rx, uint16_t len) {
  if (len == 0) return 0;
  if (send_request(pdi, ECAT_PDI_MSG_SPI, NULL, 0, tx, len) != 0) return -1;
  return await_reply(pdi, ECAT_PDI_MSG_SPI, len, rx);
}

int ecat_pdi_read_time(ecat_pdi *pdi, uint64_t *ns) {
  uint8_t reply[ECAT_PDI_TIME_SIZE];
  if (send_request(pdi, ECAT_PDI_MSG_TIME, NULL, 0, NULL, 0) != 0) return -1;
  if (await_reply(pdi, ECAT_PDI_MSG_TIME, ECAT_PDI_TIME_SIZE, reply) != 0) return -1;
  *ns = get64(reply);
  return 0;
}

int ecat_pdi_lines_now(ecat_pdi *pdi, ecat_pdi_lines *lines) {
  uint8_t reply[ECAT_PDI_LINES_SIZE];
  if (send_request(pdi, ECAT_PDI_MSG_LINES, NULL, 0, NULL, 0) != 0) return -1;
  if (await_reply(pdi, ECAT_PDI_MSG_LINES, ECAT_PDI_LINES_SIZE, reply) != 0) return -1;
  take_lines(pdi, reply);
  if (lines) *lines = pdi->lines;
  return 0;
}

static long long now_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (long long)t.tv_sec * 1000 + t.tv_nsec / 1000000;
}

int ecat_pdi_wait_irq(ecat_pdi *pdi, int timeout_ms, ecat_pdi_lines *lines) {
  long long deadline = now_ms() + (timeout_ms > 0 ? timeout_ms : 0);
  if (pdi->failed) return -1;
  for (;;) {
    struct pollfd p;
    int wait, ready;
    /* Everything that has arrived first: the lines are the latest. */
    for (;;) {
      p.fd = pdi->fd;
      p.events = POLLIN;
      p.revents = 0;
      ready = poll(&p, 1, 0);
      if (ready < 0 && errno == EINTR) continue;
      if (ready < 0) return fail(pdi, "poll: %s", strerror(errno));
      if (ready == 0) break;
      if (read_message(pdi, ECAT_PDI_MSG_NOTIFY, ECAT_PDI_LINES_SIZE, NULL) < 0) return -1;
    }
    if (pdi->lines.irq || pdi->sync_pending) {
      if (lines) {
        *lines = pdi->lines;
        lines->sync = pdi->sync_pending;
      }
      pdi->sync_pending = 0;
      return 1;
    }
    if (timeout_ms < 0) {
      wait = -1;
    } else {
      long long left = deadline - now_ms();
      if (left <= 0) return 0;
      wait = (int)left;
    }
    p.fd = pdi->fd;
    p.events = POLLIN;
    p.revents = 0;
    ready = poll(&p, 1, wait);
    if (ready < 0 && errno != EINTR) return fail(pdi, "poll: %s", strerror(errno));
  }
}
