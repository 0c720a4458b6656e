// From a device description to the configuration of the emulated silicon and
// of the state machine: the one place where od:: facts become esc:: facts, so
// the ESC, the ESM, the SII image and the ESI cannot disagree.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/expected.hpp"
#include "esc/esc_config.hpp"
#include "esc/esm_config.hpp"
#include "esc/inner_delay_figures.hpp"
#include "od/device.hpp"

namespace ecat::slave {

// The ESC as the device file describes it, with its SII image made by
// esi::write_sii from the same description (shared copy-on-write with every
// other ESC of equal image: slave/shared_eeprom.hpp).
// Its processing and per-port forwarding delays come from the figures for
// the device's ESC type (0x0000) and port types (0x0007), by default the
// datasheet table (esc/inner_delay_figures.hpp; types without a sourced
// figure get 0). SlaveOptions may override them per slave.
Expected<esc::EscConfig, std::string> esc_config_for(
    const od::DeviceDescription& device,
    std::span<const esc::InnerDelayFigures> delay_figures = esc::datasheet_inner_delays());

// What the ESM checks at Init->PreOp (mailbox SMs) and PreOp->SafeOp (SM2/SM3
// start and control byte), from the device's sync-manager layout.
esc::EsmConfig esm_config_for(const od::DeviceDescription& device);

}  // namespace ecat::slave
