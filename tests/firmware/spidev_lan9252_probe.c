/* A test firmware for a LAN9252 on Linux spidev + GPIO character devices,
 * as it would run on a board: ONLY <linux/spi/spidev.h> and <linux/gpio.h>,
 * no ecatslave header. tests/scripts/spidev_shim.sh runs it under
 * LD_PRELOAD=libecat_spidev_shim.so against `ecat-slave --pdi-host SOCK
 * --pdi-chip lan9252` (docs/firmware-in-the-loop.md).
 *
 * Usage: spidev_lan9252_probe SPIDEV GPIOCHIP IRQ-LINE v2|v1
 *        spidev_lan9252_probe SPIDEV GPIOCHIP SYNC0-LINE sync
 * (v2: GPIO_V2_GET_LINE_IOCTL and gpio_v2_line_event; v1: the deprecated
 * GPIO_GET_LINEEVENT_IOCTL and gpioevent_data; sync: see sync_test()). Prints one "name = value" line per result (checked by the script), then
 * "waiting for IRQ", and waits up to 20 s for the IRQ's falling edge (the
 * LAN9252's IRQ pin, active low) after a master writes AL control; exit 0
 * when everything came, 1 with the reason otherwise. C99 + POSIX. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <linux/gpio.h>
#include <linux/spi/spidev.h>
#include <poll.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

/* LAN9252 data sheet DS00001909: SPI instructions and system registers. */
#define INSTR_WRITE 0x02u
#define INSTR_READ 0x03u
#define REG_ECAT_CSR_DATA 0x0300u
#define REG_ECAT_CSR_CMD 0x0304u
#define REG_ID_REV 0x0050u
#define REG_IRQ_CFG 0x0054u
#define REG_INT_STS 0x0058u
#define REG_INT_EN 0x005Cu
#define REG_BYTE_TEST 0x0064u
#define CSR_BUSY 0x80000000u
#define CSR_READ 0x40000000u
#define CSR_SIZE4 (4u << 16)
#define IRQ_CFG_IRQ_EN (1u << 8) /* IRQ_POL 0: active low */
#define INT_ECAT (1u << 0)
/* ESC registers (ETG.1000.4 / ESC data sheet Section II). */
#define ESC_TYPE 0x0000u
#define ESC_AL_CONTROL 0x0120u
#define ESC_AL_EVENT_MASK 0x0204u
#define ESC_AL_EVENT_REQUEST 0x0220u
#define AL_EVENT_AL_CONTROL 0x1u
#define ESC_CYCLIC_UNIT_CONTROL 0x0980u /* bit 0: the sync unit belongs to the PDI */
#define ESC_DC_ACTIVATION 0x0981u
#define ESC_DC_SYNC0_STATUS 0x098Eu
#define ESC_DC_SYSTEM_TIME 0x0910u
#define ESC_DC_START_TIME 0x0990u
#define ESC_DC_SYNC0_CYCLE 0x09A0u
#define SYNC_OWNER_PDI 0x01u
#define ACTIVATE_SYNC_UNIT_SYNC0 0x03u
#define CSR_SIZE1 (1u << 16)
#define SYNC0_CYCLE_NS 1000000u
#define SYNC0_START_DELAY_NS 20000000u
#define SYNC0_PULSES 3

static int spi = -1;
static int v1;       /* the GPIO v1 uAPI */
static int line_fd = -1;
static int rising_only; /* sync: SYNC0 pulses, rising edges only */

static void die(const char *what) {
  fprintf(stderr, "probe: %s: %s\n", what, strerror(errno));
  exit(1);
}

static uint32_t le32(const uint8_t *p) {
  return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

/* A register read as two transfers in one chip-select window: the command
 * and address, then 4 clocks of data. */
static uint32_t reg_read(uint16_t address) {
  uint8_t cmd[3] = {INSTR_READ, (uint8_t)(address >> 8), (uint8_t)address};
  uint8_t data[4] = {0, 0, 0, 0};
  struct spi_ioc_transfer t[2];
  memset(t, 0, sizeof t);
  t[0].tx_buf = (uintptr_t)cmd;
  t[0].len = sizeof cmd;
  t[1].rx_buf = (uintptr_t)data;
  t[1].len = sizeof data;
  if (ioctl(spi, SPI_IOC_MESSAGE(2), t) != (int)(sizeof cmd + sizeof data)) die("SPI_IOC_MESSAGE(2) read");
  return le32(data);
}

/* A register write with write(2): one transaction of its own. */
static void reg_write(uint16_t address, uint32_t value) {
  uint8_t b[7] = {INSTR_WRITE, (uint8_t)(address >> 8), (uint8_t)address, (uint8_t)value, (uint8_t)(value >> 8),
                  (uint8_t)(value >> 16), (uint8_t)(value >> 24)};
  if (write(spi, b, sizeof b) != (ssize_t)sizeof b) die("write");
}

static void csr_wait(void) {
  for (int i = 0; i < 1000; ++i)
    if ((reg_read(REG_ECAT_CSR_CMD) & CSR_BUSY) == 0) return;
  fprintf(stderr, "probe: ECAT_CSR_CMD stays busy\n");
  exit(1);
}

/* ESC core register through the CSR indirect access (4 bytes). */
static uint32_t esc_read(uint16_t address) {
  reg_write(REG_ECAT_CSR_CMD, CSR_BUSY | CSR_READ | CSR_SIZE4 | address);
  csr_wait();
  return reg_read(REG_ECAT_CSR_DATA);
}

static void esc_write_sized(uint16_t address, uint32_t value, uint32_t size) {
  reg_write(REG_ECAT_CSR_DATA, value);
  reg_write(REG_ECAT_CSR_CMD, CSR_BUSY | size | address);
  csr_wait();
}

static void esc_write(uint16_t address, uint32_t value) { esc_write_sized(address, value, CSR_SIZE4); }

/* The IRQ line as an input with events on both edges. */
static void request_irq(int chip, unsigned line) {
  if (v1) {
    struct gpioevent_request r;
    memset(&r, 0, sizeof r);
    r.lineoffset = line;
    r.handleflags = GPIOHANDLE_REQUEST_INPUT;
    r.eventflags = GPIOEVENT_REQUEST_BOTH_EDGES;
    snprintf(r.consumer_label, sizeof r.consumer_label, "lan9252-irq");
    if (ioctl(chip, GPIO_GET_LINEEVENT_IOCTL, &r) != 0) die("GPIO_GET_LINEEVENT_IOCTL");
    line_fd = r.fd;
  } else {
    struct gpio_v2_line_request r;
    memset(&r, 0, sizeof r);
    r.offsets[0] = line;
    r.num_lines = 1;
    r.config.flags = GPIO_V2_LINE_FLAG_INPUT | GPIO_V2_LINE_FLAG_EDGE_RISING;
    if (!rising_only) r.config.flags |= GPIO_V2_LINE_FLAG_EDGE_FALLING;
    snprintf(r.consumer, sizeof r.consumer, "lan9252-irq");
    if (ioctl(chip, GPIO_V2_GET_LINE_IOCTL, &r) != 0) die("GPIO_V2_GET_LINE_IOCTL");
    line_fd = r.fd;
  }
}

static unsigned irq_level(void) {
  if (v1) {
    struct gpiohandle_data d;
    if (ioctl(line_fd, GPIOHANDLE_GET_LINE_VALUES_IOCTL, &d) != 0) die("GPIOHANDLE_GET_LINE_VALUES_IOCTL");
    return d.values[0];
  } else {
    struct gpio_v2_line_values v;
    memset(&v, 0, sizeof v);
    v.mask = 1;
    if (ioctl(line_fd, GPIO_V2_LINE_GET_VALUES_IOCTL, &v) != 0) die("GPIO_V2_LINE_GET_VALUES_IOCTL");
    return (unsigned)(v.bits & 1u);
  }
}

/* Waits up to `ms` for an edge and prints it; 0 on timeout. */
static int wait_edge(int ms) {
  struct pollfd p;
  p.fd = line_fd;
  p.events = POLLIN;
  p.revents = 0;
  if (poll(&p, 1, ms) != 1) return 0;
  if (v1) {
    struct gpioevent_data e;
    if (read(line_fd, &e, sizeof e) != (ssize_t)sizeof e) die("read gpioevent_data");
    printf("event id = %u (%s)\n", (unsigned)e.id, e.id == GPIOEVENT_EVENT_RISING_EDGE ? "rising" : "falling");
  } else {
    struct gpio_v2_line_event e;
    if (read(line_fd, &e, sizeof e) != (ssize_t)sizeof e) die("read gpio_v2_line_event");
    printf("event id = %u offset = %u seqno = %u line_seqno = %u\n", (unsigned)e.id, (unsigned)e.offset,
           (unsigned)e.seqno, (unsigned)e.line_seqno);
  }
  return 1;
}

/* SYNC0 on a GPIO line: once the master gave the sync unit to the PDI
 * (0x0980 bit 0, ECAT-writable only), the firmware starts SYNC0 itself
 * (cycle 1 ms, start 20 ms after the ESC's system time) and reads three
 * rising edges, acknowledging each through SYNC0 status 0x098E. */
static int sync_test(void) {
  uint64_t now;
  uint32_t control = 0;
  int i;
  printf("waiting for the sync unit\n");
  fflush(stdout);
  for (i = 0; i < 4000 && ((control = esc_read(ESC_CYCLIC_UNIT_CONTROL)) & SYNC_OWNER_PDI) == 0; ++i) {
    struct timespec t = {0, 5000000};
    nanosleep(&t, NULL);
  }
  if (i == 4000) {
    fprintf(stderr, "probe: the sync unit was never assigned to the PDI (0x0980-0x0983 = 0x%08X)\n",
            (unsigned)control);
    return 1;
  }
  now = (uint64_t)esc_read(ESC_DC_SYSTEM_TIME) | ((uint64_t)esc_read(ESC_DC_SYSTEM_TIME + 4) << 32);
  now += SYNC0_START_DELAY_NS;
  esc_write(ESC_DC_SYNC0_CYCLE, SYNC0_CYCLE_NS);
  esc_write(ESC_DC_START_TIME, (uint32_t)now);
  esc_write(ESC_DC_START_TIME + 4, (uint32_t)(now >> 32));
  esc_write_sized(ESC_DC_ACTIVATION, ACTIVATE_SYNC_UNIT_SYNC0, CSR_SIZE1);
  printf("activation = 0x%02X\n", (unsigned)(esc_read(ESC_CYCLIC_UNIT_CONTROL) >> 8) & 0xFFu);
  for (i = 0; i < SYNC0_PULSES; ++i) {
    if (!wait_edge(5000)) {
      fprintf(stderr, "probe: no SYNC0 edge %d within 5 s\n", i + 1);
      return 1;
    }
    (void)esc_read(ESC_DC_SYNC0_STATUS & ~3u); /* 0x098C..0x098F: reading 0x098E acknowledges */
  }
  printf("done\n");
  return 0;
}

int main(int argc, char **argv) {
  uint8_t mode = SPI_MODE_0, bits = 8, mode_back = 0xFF, bits_back = 0;
  uint32_t speed = 10000000, speed_back = 0;
  int chip;
  unsigned line;
  if (argc != 5 || (strcmp(argv[4], "v1") != 0 && strcmp(argv[4], "v2") != 0 && strcmp(argv[4], "sync") != 0)) {
    fprintf(stderr, "usage: %s SPIDEV GPIOCHIP LINE v2|v1|sync\n", argv[0]);
    return 2;
  }
  line = (unsigned)strtoul(argv[3], NULL, 10);
  v1 = strcmp(argv[4], "v1") == 0;
  rising_only = strcmp(argv[4], "sync") == 0;

  spi = open(argv[1], O_RDWR);
  if (spi < 0) die(argv[1]);
  if (ioctl(spi, SPI_IOC_WR_MODE, &mode) != 0 || ioctl(spi, SPI_IOC_WR_BITS_PER_WORD, &bits) != 0 ||
      ioctl(spi, SPI_IOC_WR_MAX_SPEED_HZ, &speed) != 0)
    die("SPI settings");
  if (ioctl(spi, SPI_IOC_RD_MODE, &mode_back) != 0 || ioctl(spi, SPI_IOC_RD_BITS_PER_WORD, &bits_back) != 0 ||
      ioctl(spi, SPI_IOC_RD_MAX_SPEED_HZ, &speed_back) != 0)
    die("SPI settings read back");
  printf("spi mode = %u bits = %u speed = %u\n", mode_back, bits_back, (unsigned)speed_back);

  chip = open(argv[2], O_RDWR);
  if (chip < 0) die(argv[2]);
  request_irq(chip, line);

  if (strcmp(argv[4], "sync") == 0) return sync_test();
  printf("BYTE_TEST = 0x%08X\n", (unsigned)reg_read(REG_BYTE_TEST));
  printf("ID_REV = 0x%08X\n", (unsigned)reg_read(REG_ID_REV));
  {
    /* Two reads in one message, cs_change between: two windows. */
    uint8_t a[7] = {INSTR_READ, 0, REG_BYTE_TEST}, b[7] = {INSTR_READ, 0, REG_ID_REV}, ra[7], rb[7];
    struct spi_ioc_transfer t[2];
    memset(t, 0, sizeof t);
    t[0].tx_buf = (uintptr_t)a;
    t[0].rx_buf = (uintptr_t)ra;
    t[0].len = sizeof a;
    t[0].cs_change = 1;
    t[1].tx_buf = (uintptr_t)b;
    t[1].rx_buf = (uintptr_t)rb;
    t[1].len = sizeof b;
    if (ioctl(spi, SPI_IOC_MESSAGE(2), t) != 14) die("SPI_IOC_MESSAGE(2) cs_change");
    printf("cs_change BYTE_TEST = 0x%08X ID_REV = 0x%08X\n", (unsigned)le32(ra + 3), (unsigned)le32(rb + 3));
  }
  printf("ESC 0x0000 = 0x%08X\n", (unsigned)esc_read(ESC_TYPE));

  /* The IRQ pin: AL control events only, LAN9252 IRQ enabled, active low. */
  esc_write(ESC_AL_EVENT_MASK, AL_EVENT_AL_CONTROL);
  reg_write(REG_INT_EN, INT_ECAT);
  reg_write(REG_IRQ_CFG, IRQ_CFG_IRQ_EN);
  printf("IRQ level before = %u\n", irq_level());
  printf("waiting for IRQ\n");
  fflush(stdout);
  if (!wait_edge(20000)) {
    fprintf(stderr, "probe: no IRQ edge within 20 s\n");
    return 1;
  }
  printf("IRQ level after = %u\n", irq_level());
  printf("INT_STS = 0x%08X\n", (unsigned)reg_read(REG_INT_STS));
  printf("AL event request = 0x%08X\n", (unsigned)esc_read(ESC_AL_EVENT_REQUEST));
  /* Reading AL control clears the event (0x0220 bit 0): the pin goes high. */
  printf("AL control = 0x%04X\n", (unsigned)(esc_read(ESC_AL_CONTROL) & 0xFFFFu));
  if (!wait_edge(5000)) {
    fprintf(stderr, "probe: no rising edge after AL control was read\n");
    return 1;
  }
  close(line_fd);
  close(chip);
  close(spi);
  printf("done\n");
  return 0;
}
