// The --pdi argument of ecat-slave: CHIP:SPIDEV, CHIP being "lan9252" or
// "et1100-spi" (ET1100/ET1200 SPI PDI), e.g. lan9252:/dev/spidev0.0.
#pragma once

#include <string>
#include <string_view>

#include "common/expected.hpp"

namespace ecat::pdi_spi {

enum class SpiChip : std::uint8_t { Lan9252, Et1100 };

struct PdiSpec {
  SpiChip chip = SpiChip::Lan9252;
  std::string device;
};

// The chip name alone ("lan9252", "et1100-spi").
Expected<SpiChip, std::string> parse_spi_chip(std::string_view name);
Expected<PdiSpec, std::string> parse_pdi_spec(std::string_view text);

}  // namespace ecat::pdi_spi
