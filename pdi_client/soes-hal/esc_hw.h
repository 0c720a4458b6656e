/* The SOES HAL for ecat-slave --pdi-host (esc_hw.c): what it offers beyond
 * SOES's ESC_read/ESC_write/ESC_init/ESC_reset (declared by SOES's esc.h).
 * The interrupt hooks go in esc_cfg_t's esc_hw_interrupt_enable/_disable;
 * an interrupt-driven application waits with ESC_wait_interrupt and then
 * runs what its ISR would (e.g. ecat_slv_worker). */
#ifndef SOES_HAL_ECAT_PDI_ESC_HW_H
#define SOES_HAL_ECAT_PDI_ESC_HW_H

#include <stdint.h>

#include "ecat_pdi.h"

void ESC_interrupt_enable(uint32_t mask);
void ESC_interrupt_disable(uint32_t mask);
/* 1: the IRQ line is asserted or a SYNC pulse came; 0: `timeout_ms` passed. */
int ESC_wait_interrupt(int timeout_ms);
/* The connection, for what else the firmware reads (ecat_pdi_read_time). */
ecat_pdi *ESC_pdi(void);

#endif
