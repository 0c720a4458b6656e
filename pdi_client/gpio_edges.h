/* The emulated ESC's output lines as GPIO lines, for the gpiochip side of
 * the spidev shim (spidev_shim.c, docs/firmware-in-the-loop.md): which edges
 * a change of the host's lines (ecat_pdi_lines) makes, and which event a
 * line request sees for each. No I/O here (tested in
 * tests/pdi_host/spidev_shim_logic_test.cpp). C99. */
#ifndef ECAT_GPIO_EDGES_H
#define ECAT_GPIO_EDGES_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Line offsets on the emulated chip and the IRQ pin's polarity. */
typedef struct gpio_line_map {
  uint32_t irq;       /* $ECAT_GPIO_IRQ_LINE, default 0 */
  uint32_t sync0;     /* $ECAT_GPIO_SYNC0_LINE, default 1 */
  uint32_t sync1;     /* $ECAT_GPIO_SYNC1_LINE, default 2 */
  int irq_active_low; /* $ECAT_GPIO_IRQ_ACTIVE_LOW, default 1 (LAN9252 IRQ_CFG.IRQ_POL 0 at reset) */
} gpio_line_map;

/* Event ids, as GPIO_V2_LINE_EVENT_RISING_EDGE / _FALLING_EDGE (and v1's
 * GPIOEVENT_EVENT_RISING_EDGE / _FALLING_EDGE). */
enum { GPIO_EDGE_RISING = 1, GPIO_EDGE_FALLING = 2 };
enum { GPIO_MAX_EDGES = 5 }; /* one IRQ edge, two per SYNC pulse */

typedef struct gpio_edge {
  uint32_t offset;
  uint32_t id; /* physical edge: GPIO_EDGE_RISING or _FALLING */
} gpio_edge;

/* The IRQ pin's electrical level (1 high) for the ESC's IRQ line asserted or not. */
int gpio_irq_level(const gpio_line_map *map, int asserted);

/* The physical edges for the IRQ line going from `irq_was` to `irq_now`
 * (asserted flags) and the SYNC pulses in `sync` (ECAT_PDI_SYNC0 / _SYNC1
 * bits): the IRQ edge first, then each SYNC pulse as a rising and a falling
 * edge (SYNC outputs active high, a pulse shorter than the host's notice).
 * Returns how many were written to `out`. */
size_t gpio_physical_edges(const gpio_line_map *map, int irq_was, int irq_now, uint8_t sync,
                           gpio_edge out[GPIO_MAX_EDGES]);

/* The event a line requested with GPIO v2 `flags` sees for a physical edge
 * (GPIO_V2_LINE_FLAG_ACTIVE_LOW inverts, GPIO_V2_LINE_FLAG_EDGE_RISING /
 * _FALLING select): GPIO_EDGE_RISING, GPIO_EDGE_FALLING, or 0 for none. */
uint32_t gpio_event_for(uint64_t flags, uint32_t physical_id);

#ifdef __cplusplus
}
#endif

#endif /* ECAT_GPIO_EDGES_H */
