/* LD_PRELOAD shim for firmware built for a LAN9252 on Linux spidev and GPIO
 * character devices (issue 28 item 2; docs/firmware-in-the-loop.md "spidev
 * and gpiochip firmware").
 *
 *   /dev/spidevB.C   open, close, ioctl SPI_IOC_MESSAGE(N) and the mode /
 *                    bits-per-word / speed settings, read, write: each
 *                    chip-select window (spidev_frame.h) is one SPI
 *                    transaction of libecat_pdi against `ecat-slave
 *                    --pdi-host SOCKET --pdi-chip lan9252|et1100-spi`.
 *   /dev/gpiochipN   the GPIO v2 uAPI (chip info, line info, line request,
 *                    get/set values, set config; edge events) and v1's
 *                    GPIO_GET_LINEEVENT_IOCTL: the ESC's IRQ, SYNC0 and
 *                    SYNC1 outputs are lines of the chip (gpio_edges.h).
 *
 * A line request's descriptor is the read end of a pipe: the shim writes
 * each event (struct gpio_v2_line_event, or v1's gpioevent_data) into it, so
 * read(), poll() and select() on it are the C library's own. A thread
 * (started with the first line request) reads the host's LINES notifications
 * while the firmware is not in an SPI call; both share the one connection
 * under a mutex (the host takes one firmware at a time).
 *
 * Which paths: $ECAT_SPIDEV_DEVICE / $ECAT_GPIOCHIP_DEVICE when set, else
 * every /dev/spidev* / /dev/gpiochip*. The spidev and chip descriptors are
 * real ones (of /dev/null), so they never collide with other files.
 * C99 with POSIX threads and dlsym(RTLD_NEXT) (hence _GNU_SOURCE). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <linux/gpio.h>
#include <linux/spi/spidev.h>
#include <poll.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

#include "ecat_pdi.h"
#include "ecat_pdi_protocol.h"
#include "gpio_edges.h"
#include "spidev_frame.h"

enum {
  kMaxFds = 16,       /* spidev + gpiochip descriptors open at once */
  kMaxRequests = 16,  /* line requests at once */
  kChipLines = 32,    /* lines of the emulated gpiochip */
  kSpiModeMask = 0x3, /* CPHA | CPOL: the modes the shim remembers and reports */
  kBitsPerByte = 8
};

static const char kChipName[] = "gpiochip-ecat";
static const char kChipLabel[] = "ecatslave emulated ESC";

typedef struct spi_settings {
  uint32_t mode;
  uint8_t bits_per_word;
  uint32_t max_speed_hz;
} spi_settings;

typedef enum fd_kind { FD_NONE, FD_SPIDEV, FD_GPIOCHIP } fd_kind;
typedef struct shim_fd {
  int fd;
  fd_kind kind;
  spi_settings spi;
} shim_fd;

typedef struct line_request {
  int used;     /* 0: slot free */
  int read_fd;  /* the firmware's descriptor */
  int write_fd; /* the shim's end */
  int v1;       /* 1: a v1 line event request (gpioevent_data) */
  uint32_t num_lines;
  uint32_t offsets[GPIO_V2_LINES_MAX];
  uint64_t flags[GPIO_V2_LINES_MAX];
  uint32_t line_seqno[GPIO_V2_LINES_MAX];
  uint32_t seqno;
  uint64_t outputs; /* values set on output lines, by index */
} line_request;

/* Recursive: libecat_pdi closes its socket with close(), which comes here. */
static pthread_mutex_t shim_lock = PTHREAD_RECURSIVE_MUTEX_INITIALIZER_NP;
static ecat_pdi *shim_pdi;
static int shim_users; /* open descriptors that need the connection */
static shim_fd shim_fds[kMaxFds];
static line_request shim_requests[kMaxRequests];
static gpio_line_map shim_map;
static int shim_irq;      /* the IRQ line as last seen (asserted) */
static uint64_t shim_dropped; /* events dropped on a full pipe */
static pthread_t shim_thread;
static int shim_thread_running;
static int shim_wake[2] = {-1, -1}; /* stops the thread */
static uint8_t shim_scratch[ECAT_PDI_MAX_PAYLOAD];

typedef int (*open_fn)(const char *, int, ...);
typedef int (*openat_fn)(int, const char *, int, ...);
typedef int (*close_fn)(int);
typedef int (*ioctl_fn)(int, unsigned long, ...);
typedef ssize_t (*read_fn)(int, void *, size_t);
typedef ssize_t (*write_fn)(int, const void *, size_t);

/* The C library's own function `name` into the function pointer at `slot`
 * (as lan9252_shim.c: dlsym's object pointer copied into a function pointer). */
static void next(void *slot, size_t size, const char *name) {
  void *f = dlsym(RTLD_NEXT, name);
  if (f == NULL || size != sizeof f) {
    fprintf(stderr, "ecat spidev shim: %s not found in the C library\n", name);
    abort();
  }
  memcpy(slot, &f, sizeof f);
}

static int real_close(int fd) {
  static close_fn f;
  if (f == NULL) next(&f, sizeof f, "close");
  return f(fd);
}

static ssize_t real_write(int fd, const void *buf, size_t n) {
  static write_fn f;
  if (f == NULL) next(&f, sizeof f, "write");
  return f(fd, buf, n);
}

static int matches(const char *path, const char *env, const char *prefix) {
  const char *want = getenv(env);
  if (path == NULL) return 0;
  if (want != NULL && want[0] != '\0') return strcmp(path, want) == 0;
  return strncmp(path, prefix, strlen(prefix)) == 0 && path[strlen(prefix)] != '\0';
}

static uint32_t env_line(const char *name, uint32_t fallback) {
  const char *v = getenv(name);
  char *end;
  unsigned long n;
  if (v == NULL || v[0] == '\0') return fallback;
  n = strtoul(v, &end, 10);
  if (*end != '\0' || n >= kChipLines) {
    fprintf(stderr, "ecat spidev shim: %s=%s: not a line number 0..%d, using %u\n", name, v, kChipLines - 1,
            (unsigned)fallback);
    return fallback;
  }
  return (uint32_t)n;
}

/* The host went away or refused a transaction: the chip is gone. */
static void device_lost(void) {
  fprintf(stderr, "ecat spidev shim: %s\n", ecat_pdi_error(shim_pdi));
  exit(1);
}

/* Under the lock: connects on the first user. 0, or -1 with errno. */
static int acquire(void) {
  if (shim_pdi == NULL) {
    const char *sock = getenv("ECAT_PDI_SOCKET");
    char err[256];
    ecat_pdi *p;
    if (sock == NULL || sock[0] == '\0') {
      fprintf(stderr, "ecat spidev shim: ECAT_PDI_SOCKET is not set (the path of ecat-slave --pdi-host)\n");
      errno = ENODEV;
      return -1;
    }
    p = ecat_pdi_connect(sock, err, sizeof err);
    if (p == NULL) {
      fprintf(stderr, "ecat spidev shim: %s\n", err);
      errno = ENODEV;
      return -1;
    }
    if (ecat_pdi_chip(p) == (int)ECAT_PDI_CHIP_DIRECT) {
      fprintf(stderr, "ecat spidev shim: the host offers the direct PDI, not SPI (ecat-slave --pdi-chip lan9252 or "
                      "et1100-spi)\n");
      ecat_pdi_close(p);
      errno = ENODEV;
      return -1;
    }
    shim_pdi = p;
    shim_irq = 0;
    shim_map.irq = env_line("ECAT_GPIO_IRQ_LINE", 0);
    shim_map.sync0 = env_line("ECAT_GPIO_SYNC0_LINE", 1);
    shim_map.sync1 = env_line("ECAT_GPIO_SYNC1_LINE", 2);
    {
      const char *low = getenv("ECAT_GPIO_IRQ_ACTIVE_LOW");
      shim_map.irq_active_low = low == NULL || low[0] == '\0' || strcmp(low, "0") != 0;
    }
  }
  ++shim_users;
  return 0;
}

/* Under the lock: the last user closes the connection. */
static void release(void) {
  if (--shim_users > 0) return;
  ecat_pdi_close(shim_pdi);
  shim_pdi = NULL;
}

static shim_fd *find_fd(int fd) {
  for (int i = 0; i < kMaxFds; ++i)
    if (shim_fds[i].kind != FD_NONE && shim_fds[i].fd == fd) return &shim_fds[i];
  return NULL;
}

static line_request *find_request(int fd) {
  for (int i = 0; i < kMaxRequests; ++i)
    if (shim_requests[i].used && shim_requests[i].read_fd == fd) return &shim_requests[i];
  return NULL;
}

static uint64_t now_ns(uint64_t flags) {
  struct timespec t;
  clock_gettime((flags & GPIO_V2_LINE_FLAG_EVENT_CLOCK_REALTIME) ? CLOCK_REALTIME : CLOCK_MONOTONIC, &t);
  return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

/* Under the lock: one physical edge to every request watching its line. */
static void deliver(const gpio_edge *edge) {
  for (int r = 0; r < kMaxRequests; ++r) {
    line_request *q = &shim_requests[r];
    if (!q->used) continue;
    for (uint32_t i = 0; i < q->num_lines; ++i) {
      uint32_t id;
      ssize_t n;
      if (q->offsets[i] != edge->offset) continue;
      id = gpio_event_for(q->flags[i], edge->id);
      if (id == 0) continue;
      ++q->seqno;
      ++q->line_seqno[i];
      if (q->v1) {
        struct gpioevent_data e;
        memset(&e, 0, sizeof e);
        e.timestamp = now_ns(q->flags[i]);
        e.id = id;
        n = real_write(q->write_fd, &e, sizeof e);
      } else {
        struct gpio_v2_line_event e;
        memset(&e, 0, sizeof e);
        e.timestamp_ns = now_ns(q->flags[i]);
        e.id = id;
        e.offset = edge->offset;
        e.seqno = q->seqno;
        e.line_seqno = q->line_seqno[i];
        n = real_write(q->write_fd, &e, sizeof e);
      }
      if (n < 0) ++shim_dropped; /* the pipe is full: dropped, as the kernel's kfifo drops */
    }
  }
}

/* Under the lock: the notifications that have arrived, as edges. */
static void update_lines(void) {
  ecat_pdi_lines lines;
  gpio_edge edges[GPIO_MAX_EDGES];
  int r;
  size_t n;
  if (shim_pdi == NULL) return;
  r = ecat_pdi_wait_irq(shim_pdi, 0, &lines);
  if (r < 0) device_lost();
  if (r == 0) {
    lines.irq = 0; /* neither the IRQ asserted nor a SYNC pulse */
    lines.sync = 0;
  }
  n = gpio_physical_edges(&shim_map, shim_irq, lines.irq, lines.sync, edges);
  shim_irq = lines.irq != 0;
  for (size_t i = 0; i < n; ++i) deliver(&edges[i]);
}

/* Reads the host's notifications while the firmware is elsewhere. */
static void *lines_thread(void *arg) {
  (void)arg;
  for (;;) {
    struct pollfd p[2];
    int fd;
    pthread_mutex_lock(&shim_lock);
    fd = shim_pdi != NULL ? ecat_pdi_fd(shim_pdi) : -1;
    pthread_mutex_unlock(&shim_lock);
    p[0].fd = fd;
    p[0].events = POLLIN;
    p[0].revents = 0;
    p[1].fd = shim_wake[0];
    p[1].events = POLLIN;
    p[1].revents = 0;
    if (poll(p, 2, -1) < 0 && errno != EINTR) break;
    if (p[1].revents != 0) break;
    if (p[0].revents != 0) {
      pthread_mutex_lock(&shim_lock);
      update_lines();
      pthread_mutex_unlock(&shim_lock);
    }
  }
  return NULL;
}

/* Under the lock. */
static int start_thread(void) {
  if (shim_thread_running) return 0;
  if (pipe2(shim_wake, O_CLOEXEC) != 0) return -1;
  if (pthread_create(&shim_thread, NULL, lines_thread, NULL) != 0) {
    real_close(shim_wake[0]);
    real_close(shim_wake[1]);
    errno = EAGAIN;
    return -1;
  }
  shim_thread_running = 1;
  return 0;
}

/* Called without the lock held by this thread (joins the thread, which takes it). */
static void stop_thread(void) {
  char b = 0;
  if (!shim_thread_running) return;
  if (real_write(shim_wake[1], &b, 1) != 1) abort();
  pthread_join(shim_thread, NULL);
  real_close(shim_wake[0]);
  real_close(shim_wake[1]);
  shim_wake[0] = shim_wake[1] = -1;
  shim_thread_running = 0;
}

static int any_request(void) {
  for (int i = 0; i < kMaxRequests; ++i)
    if (shim_requests[i].used) return 1;
  return 0;
}

/* --- open / close ------------------------------------------------------ */

static int open_device(fd_kind kind, open_fn real_open) {
  int fd, slot = -1;
  pthread_mutex_lock(&shim_lock);
  for (int i = 0; i < kMaxFds && slot < 0; ++i)
    if (shim_fds[i].kind == FD_NONE) slot = i;
  if (slot < 0) {
    pthread_mutex_unlock(&shim_lock);
    errno = EMFILE;
    return -1;
  }
  if (acquire() != 0) {
    pthread_mutex_unlock(&shim_lock);
    return -1;
  }
  fd = real_open("/dev/null", O_RDWR | O_CLOEXEC);
  if (fd < 0) {
    int e = errno;
    release();
    pthread_mutex_unlock(&shim_lock);
    errno = e;
    return -1;
  }
  shim_fds[slot].fd = fd;
  shim_fds[slot].kind = kind;
  shim_fds[slot].spi.mode = SPI_MODE_0;
  shim_fds[slot].spi.bits_per_word = kBitsPerByte;
  shim_fds[slot].spi.max_speed_hz = 0;
  pthread_mutex_unlock(&shim_lock);
  return fd;
}

static fd_kind kind_of(const char *path) {
  if (matches(path, "ECAT_SPIDEV_DEVICE", "/dev/spidev")) return FD_SPIDEV;
  if (matches(path, "ECAT_GPIOCHIP_DEVICE", "/dev/gpiochip")) return FD_GPIOCHIP;
  return FD_NONE;
}

static int open_common(const char *name, const char *path, int flags, va_list ap) {
  open_fn real;
  fd_kind kind = kind_of(path);
  next(&real, sizeof real, name);
  if (kind != FD_NONE) return open_device(kind, real);
  if ((flags & O_CREAT) != 0 || (flags & O_TMPFILE) == O_TMPFILE) return real(path, flags, va_arg(ap, int));
  return real(path, flags);
}

int open(const char *path, int flags, ...) {
  va_list ap;
  int r;
  va_start(ap, flags);
  r = open_common("open", path, flags, ap);
  va_end(ap);
  return r;
}

int open64(const char *path, int flags, ...) {
  va_list ap;
  int r;
  va_start(ap, flags);
  r = open_common("open64", path, flags, ap);
  va_end(ap);
  return r;
}

static int openat_common(const char *name, int dirfd, const char *path, int flags, va_list ap) {
  openat_fn real;
  fd_kind kind = kind_of(path);
  next(&real, sizeof real, name);
  if (kind != FD_NONE) {
    open_fn plain;
    next(&plain, sizeof plain, "open");
    return open_device(kind, plain);
  }
  if ((flags & O_CREAT) != 0 || (flags & O_TMPFILE) == O_TMPFILE) return real(dirfd, path, flags, va_arg(ap, int));
  return real(dirfd, path, flags);
}

int openat(int dirfd, const char *path, int flags, ...) {
  va_list ap;
  int r;
  va_start(ap, flags);
  r = openat_common("openat", dirfd, path, flags, ap);
  va_end(ap);
  return r;
}

int openat64(int dirfd, const char *path, int flags, ...) {
  va_list ap;
  int r;
  va_start(ap, flags);
  r = openat_common("openat64", dirfd, path, flags, ap);
  va_end(ap);
  return r;
}

int close(int fd) {
  int stop = 0;
  pthread_mutex_lock(&shim_lock);
  if (fd >= 0) {
    shim_fd *s = find_fd(fd);
    line_request *q = s == NULL ? find_request(fd) : NULL;
    if (s != NULL) {
      s->kind = FD_NONE;
      release();
    } else if (q != NULL) {
      real_close(q->write_fd);
      q->used = 0;
      release();
      stop = !any_request();
    }
  }
  pthread_mutex_unlock(&shim_lock);
  if (stop) stop_thread();
  return real_close(fd);
}

/* --- spidev ------------------------------------------------------------ */

static int spi_window(void *ctx, uint8_t *buf, size_t len) {
  (void)ctx;
  return ecat_pdi_spi_transfer(shim_pdi, buf, buf, (uint16_t)len);
}

/* Under the lock: one message; spidev's return value or -1 with errno. */
static int spi_message(const struct spi_ioc_transfer *xfers, unsigned n) {
  long r = spidev_run_message(xfers, n, shim_scratch, sizeof shim_scratch, spi_window, NULL);
  if (r == -EIO) device_lost();
  update_lines();
  if (r < 0) {
    errno = (int)-r;
    return -1;
  }
  return (int)r;
}

static int spi_ioctl(shim_fd *s, unsigned long request, void *arg) {
  spi_settings *c = &s->spi;
  if (arg == NULL) {
    errno = EFAULT;
    return -1;
  }
  if (_IOC_TYPE(request) == SPI_IOC_MAGIC && _IOC_NR(request) == 0 && _IOC_DIR(request) == _IOC_WRITE) {
    size_t size = _IOC_SIZE(request);
    if (size % sizeof(struct spi_ioc_transfer) != 0) {
      errno = EINVAL;
      return -1;
    }
    return spi_message((const struct spi_ioc_transfer *)arg, (unsigned)(size / sizeof(struct spi_ioc_transfer)));
  }
  switch (request) {
    case SPI_IOC_RD_MODE: *(uint8_t *)arg = (uint8_t)c->mode; return 0;
    case SPI_IOC_RD_MODE32: *(uint32_t *)arg = c->mode; return 0;
    case SPI_IOC_WR_MODE: c->mode = *(const uint8_t *)arg; return 0;
    case SPI_IOC_WR_MODE32: c->mode = *(const uint32_t *)arg; return 0;
    case SPI_IOC_RD_LSB_FIRST: *(uint8_t *)arg = (c->mode & SPI_LSB_FIRST) != 0; return 0;
    case SPI_IOC_WR_LSB_FIRST:
      if (*(const uint8_t *)arg != 0) break; /* the chips are MSB first */
      return 0;
    case SPI_IOC_RD_BITS_PER_WORD: *(uint8_t *)arg = c->bits_per_word; return 0;
    case SPI_IOC_WR_BITS_PER_WORD: {
      uint8_t b = *(const uint8_t *)arg;
      if (b != 0 && b != kBitsPerByte) break;
      c->bits_per_word = kBitsPerByte;
      return 0;
    }
    case SPI_IOC_RD_MAX_SPEED_HZ: *(uint32_t *)arg = c->max_speed_hz; return 0;
    case SPI_IOC_WR_MAX_SPEED_HZ: c->max_speed_hz = *(const uint32_t *)arg; return 0;
    default: errno = ENOTTY; return -1;
  }
  errno = EINVAL;
  return -1;
}

/* read/write on spidev: one half-duplex transfer, its own chip-select window. */
static ssize_t spi_rw(void *rx, const void *tx, size_t n) {
  struct spi_ioc_transfer t;
  int r;
  if (n == 0) return 0;
  if (n > ECAT_PDI_MAX_PAYLOAD) n = ECAT_PDI_MAX_PAYLOAD;
  memset(&t, 0, sizeof t);
  t.tx_buf = (uint64_t)(uintptr_t)tx;
  t.rx_buf = (uint64_t)(uintptr_t)rx;
  t.len = (uint32_t)n;
  pthread_mutex_lock(&shim_lock);
  r = spi_message(&t, 1);
  pthread_mutex_unlock(&shim_lock);
  return r;
}

ssize_t read(int fd, void *buf, size_t n) {
  static read_fn real;
  int spi;
  pthread_mutex_lock(&shim_lock);
  spi = fd >= 0 && find_fd(fd) != NULL && find_fd(fd)->kind == FD_SPIDEV;
  pthread_mutex_unlock(&shim_lock);
  if (spi) return spi_rw(buf, NULL, n);
  if (real == NULL) next(&real, sizeof real, "read");
  return real(fd, buf, n);
}

ssize_t write(int fd, const void *buf, size_t n) {
  int spi;
  pthread_mutex_lock(&shim_lock);
  spi = fd >= 0 && find_fd(fd) != NULL && find_fd(fd)->kind == FD_SPIDEV;
  pthread_mutex_unlock(&shim_lock);
  if (spi) return spi_rw(NULL, buf, n);
  return real_write(fd, buf, n);
}

/* --- gpiochip ---------------------------------------------------------- */

static const char *line_name(uint32_t offset) {
  if (offset == shim_map.irq) return "IRQ";
  if (offset == shim_map.sync0) return "SYNC0";
  if (offset == shim_map.sync1) return "SYNC1";
  return "";
}

static int is_input_line(uint32_t offset) {
  return offset == shim_map.irq || offset == shim_map.sync0 || offset == shim_map.sync1;
}

/* The flags of line `i` of a v2 request: config.flags unless an attribute sets them. */
static uint64_t flags_of(const struct gpio_v2_line_config *c, uint32_t i) {
  for (uint32_t a = 0; a < c->num_attrs && a < GPIO_V2_LINE_NUM_ATTRS_MAX; ++a)
    if (c->attrs[a].attr.id == GPIO_V2_LINE_ATTR_ID_FLAGS && (c->attrs[a].mask >> i) & 1u)
      return c->attrs[a].attr.flags;
  return c->flags;
}

static int valid_flags(uint32_t offset, uint64_t flags) {
  int edge = (flags & (GPIO_V2_LINE_FLAG_EDGE_RISING | GPIO_V2_LINE_FLAG_EDGE_FALLING)) != 0;
  int input = (flags & GPIO_V2_LINE_FLAG_INPUT) != 0, output = (flags & GPIO_V2_LINE_FLAG_OUTPUT) != 0;
  if (input && output) return 0;
  if (edge && !input) return 0; /* as the kernel: edges only on inputs */
  if (output && is_input_line(offset)) return 0; /* the ESC drives these */
  return 1;
}

/* Under the lock: a new request on `num` offsets; its descriptor or -1. */
static int new_request(const uint32_t *offsets, const uint64_t *flags, uint32_t num, int v1, uint64_t outputs) {
  int p[2];
  line_request *q = NULL;
  for (int i = 0; i < kMaxRequests && q == NULL; ++i)
    if (!shim_requests[i].used) q = &shim_requests[i];
  if (q == NULL) {
    errno = EBUSY;
    return -1;
  }
  if (acquire() != 0) return -1;
  if (start_thread() != 0 || pipe2(p, O_CLOEXEC) != 0) {
    int e = errno;
    release();
    errno = e;
    return -1;
  }
  if (fcntl(p[1], F_SETFL, O_NONBLOCK) != 0) {
    int e = errno;
    real_close(p[0]);
    real_close(p[1]);
    release();
    errno = e;
    return -1;
  }
  memset(q, 0, sizeof *q);
  q->used = 1;
  q->read_fd = p[0];
  q->write_fd = p[1];
  q->v1 = v1;
  q->num_lines = num;
  memcpy(q->offsets, offsets, num * sizeof *offsets);
  memcpy(q->flags, flags, num * sizeof *flags);
  q->outputs = outputs;
  return p[0];
}

/* Under the lock: the logical value of line `i` of a request. */
static int line_value(line_request *q, uint32_t i) {
  uint32_t off = q->offsets[i];
  int level;
  if (q->flags[i] & GPIO_V2_LINE_FLAG_OUTPUT) return (int)((q->outputs >> i) & 1u);
  if (off == shim_map.irq) {
    ecat_pdi_lines lines;
    if (ecat_pdi_lines_now(shim_pdi, &lines) != 0) device_lost();
    update_lines();
    level = gpio_irq_level(&shim_map, lines.irq);
  } else {
    level = 0; /* SYNC pulses are over by the time anyone reads; other lines read low */
  }
  return (q->flags[i] & GPIO_V2_LINE_FLAG_ACTIVE_LOW) ? !level : level;
}

static int chip_ioctl(unsigned long request, void *arg) {
  if (arg == NULL) {
    errno = EFAULT;
    return -1;
  }
  if (request == GPIO_GET_CHIPINFO_IOCTL) {
    struct gpiochip_info *i = arg;
    memset(i, 0, sizeof *i);
    snprintf(i->name, sizeof i->name, "%s", kChipName);
    snprintf(i->label, sizeof i->label, "%s", kChipLabel);
    i->lines = kChipLines;
    return 0;
  }
  if (request == GPIO_V2_GET_LINEINFO_IOCTL || request == GPIO_V2_GET_LINEINFO_WATCH_IOCTL) {
    struct gpio_v2_line_info *i = arg;
    uint32_t off = i->offset;
    if (off >= kChipLines) {
      errno = EINVAL;
      return -1;
    }
    memset(i, 0, sizeof *i);
    i->offset = off;
    snprintf(i->name, sizeof i->name, "%s", line_name(off));
    i->flags = is_input_line(off) ? GPIO_V2_LINE_FLAG_INPUT : 0;
    return 0;
  }
  if (request == GPIO_V2_GET_LINE_IOCTL) {
    struct gpio_v2_line_request *r = arg;
    uint64_t flags[GPIO_V2_LINES_MAX], outputs = 0;
    int fd;
    if (r->num_lines == 0 || r->num_lines > GPIO_V2_LINES_MAX || r->config.num_attrs > GPIO_V2_LINE_NUM_ATTRS_MAX) {
      errno = EINVAL;
      return -1;
    }
    for (uint32_t i = 0; i < r->num_lines; ++i) {
      if (r->offsets[i] >= kChipLines) {
        errno = EINVAL;
        return -1;
      }
      flags[i] = flags_of(&r->config, i);
      if (!valid_flags(r->offsets[i], flags[i])) {
        errno = EINVAL;
        return -1;
      }
    }
    for (uint32_t a = 0; a < r->config.num_attrs; ++a)
      if (r->config.attrs[a].attr.id == GPIO_V2_LINE_ATTR_ID_OUTPUT_VALUES)
        outputs |= r->config.attrs[a].attr.values & r->config.attrs[a].mask;
    fd = new_request(r->offsets, flags, r->num_lines, 0, outputs);
    if (fd < 0) return -1;
    r->fd = fd;
    return 0;
  }
  if (request == GPIO_GET_LINEEVENT_IOCTL) {
    struct gpioevent_request *r = arg;
    uint64_t flags = GPIO_V2_LINE_FLAG_INPUT;
    int fd;
    if (r->lineoffset >= kChipLines || (r->handleflags & GPIOHANDLE_REQUEST_OUTPUT)) {
      errno = EINVAL;
      return -1;
    }
    if (r->handleflags & GPIOHANDLE_REQUEST_ACTIVE_LOW) flags |= GPIO_V2_LINE_FLAG_ACTIVE_LOW;
    if (r->eventflags & GPIOEVENT_REQUEST_RISING_EDGE) flags |= GPIO_V2_LINE_FLAG_EDGE_RISING;
    if (r->eventflags & GPIOEVENT_REQUEST_FALLING_EDGE) flags |= GPIO_V2_LINE_FLAG_EDGE_FALLING;
    fd = new_request(&r->lineoffset, &flags, 1, 1, 0);
    if (fd < 0) return -1;
    r->fd = fd;
    return 0;
  }
  errno = ENOTTY;
  return -1;
}

static int request_ioctl(line_request *q, unsigned long request, void *arg) {
  if (arg == NULL) {
    errno = EFAULT;
    return -1;
  }
  if (!q->v1 && request == GPIO_V2_LINE_GET_VALUES_IOCTL) {
    struct gpio_v2_line_values *v = arg;
    uint64_t bits = 0;
    for (uint32_t i = 0; i < q->num_lines; ++i)
      if ((v->mask >> i) & 1u) bits |= (uint64_t)line_value(q, i) << i;
    v->bits = bits;
    return 0;
  }
  if (!q->v1 && request == GPIO_V2_LINE_SET_VALUES_IOCTL) {
    const struct gpio_v2_line_values *v = arg;
    for (uint32_t i = 0; i < q->num_lines; ++i)
      if (((v->mask >> i) & 1u) && !(q->flags[i] & GPIO_V2_LINE_FLAG_OUTPUT)) {
        errno = EPERM; /* as the kernel: not an output */
        return -1;
      }
    q->outputs = (q->outputs & ~v->mask) | (v->bits & v->mask);
    return 0;
  }
  if (!q->v1 && request == GPIO_V2_LINE_SET_CONFIG_IOCTL) {
    const struct gpio_v2_line_config *c = arg;
    uint64_t flags[GPIO_V2_LINES_MAX];
    if (c->num_attrs > GPIO_V2_LINE_NUM_ATTRS_MAX) {
      errno = EINVAL;
      return -1;
    }
    for (uint32_t i = 0; i < q->num_lines; ++i) {
      flags[i] = flags_of(c, i);
      if (!valid_flags(q->offsets[i], flags[i])) {
        errno = EINVAL;
        return -1;
      }
    }
    memcpy(q->flags, flags, q->num_lines * sizeof *flags);
    return 0;
  }
  if (q->v1 && request == GPIOHANDLE_GET_LINE_VALUES_IOCTL) {
    struct gpiohandle_data *d = arg;
    memset(d, 0, sizeof *d);
    d->values[0] = (uint8_t)line_value(q, 0);
    return 0;
  }
  errno = ENOTTY;
  return -1;
}

int ioctl(int fd, unsigned long request, ...) {
  static ioctl_fn real;
  va_list ap;
  void *arg;
  shim_fd *s;
  line_request *q;
  int r;
  va_start(ap, request);
  arg = va_arg(ap, void *);
  va_end(ap);
  pthread_mutex_lock(&shim_lock);
  s = fd >= 0 ? find_fd(fd) : NULL;
  q = fd >= 0 && s == NULL ? find_request(fd) : NULL;
  if (s == NULL && q == NULL) {
    pthread_mutex_unlock(&shim_lock);
    if (real == NULL) next(&real, sizeof real, "ioctl");
    return real(fd, request, arg);
  }
  if (s != NULL && s->kind == FD_SPIDEV) {
    r = spi_ioctl(s, request, arg);
  } else if (s != NULL) {
    r = chip_ioctl(request, arg);
  } else {
    r = request_ioctl(q, request, arg);
  }
  pthread_mutex_unlock(&shim_lock);
  return r;
}
