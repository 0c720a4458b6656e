/* gpio_edges.h: host lines -> GPIO edges and events. */
#include "gpio_edges.h"

#include <linux/gpio.h>

#include "ecat_pdi_protocol.h"

int gpio_irq_level(const gpio_line_map *map, int asserted) {
  return map->irq_active_low ? !asserted : asserted != 0;
}

static size_t pulse(uint32_t offset, gpio_edge *out) {
  out[0].offset = offset;
  out[0].id = GPIO_EDGE_RISING;
  out[1].offset = offset;
  out[1].id = GPIO_EDGE_FALLING;
  return 2;
}

size_t gpio_physical_edges(const gpio_line_map *map, int irq_was, int irq_now, uint8_t sync,
                           gpio_edge out[GPIO_MAX_EDGES]) {
  size_t n = 0;
  if ((irq_was != 0) != (irq_now != 0)) {
    out[n].offset = map->irq;
    out[n].id = gpio_irq_level(map, irq_now) ? GPIO_EDGE_RISING : GPIO_EDGE_FALLING;
    ++n;
  }
  if (sync & ECAT_PDI_SYNC0) n += pulse(map->sync0, out + n);
  if (sync & ECAT_PDI_SYNC1) n += pulse(map->sync1, out + n);
  return n;
}

uint32_t gpio_event_for(uint64_t flags, uint32_t physical_id) {
  uint32_t logical = physical_id;
  if (flags & GPIO_V2_LINE_FLAG_ACTIVE_LOW) logical = physical_id == GPIO_EDGE_RISING ? GPIO_EDGE_FALLING : GPIO_EDGE_RISING;
  if (logical == GPIO_EDGE_RISING && (flags & GPIO_V2_LINE_FLAG_EDGE_RISING)) return GPIO_EDGE_RISING;
  if (logical == GPIO_EDGE_FALLING && (flags & GPIO_V2_LINE_FLAG_EDGE_FALLING)) return GPIO_EDGE_FALLING;
  return 0;
}
