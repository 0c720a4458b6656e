// Which PDI a firmware process reaches the ESC through (--pdi-chip): the
// ESC's memory directly (address + length, as SOES's ESC_read/ESC_write),
// or the SPI transactions of an emulated LAN9252 or ET1100 SPI slave
// (pdi_spi/emulated_*), byte-exact as on the chip.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "common/expected.hpp"
#include "pdi_client/ecat_pdi_protocol.h"

namespace ecat::pdi_host {

enum class PdiChip : std::uint8_t {
  Direct = ECAT_PDI_CHIP_DIRECT,
  Lan9252 = ECAT_PDI_CHIP_LAN9252,
  Et1100Spi = ECAT_PDI_CHIP_ET1100_SPI,
};

// "direct", "lan9252" or "et1100-spi".
Expected<PdiChip, std::string> parse_pdi_chip(std::string_view text);
const char* describe(PdiChip chip) noexcept;

}  // namespace ecat::pdi_host
