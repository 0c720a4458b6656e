#include "pdi_spi/pdi_spec.hpp"

#include <fmt/format.h>

namespace ecat::pdi_spi {

Expected<SpiChip, std::string> parse_spi_chip(std::string_view name) {
  if (name == "lan9252") return SpiChip::Lan9252;
  if (name == "et1100-spi") return SpiChip::Et1100;
  return fail(fmt::format("unknown PDI chip '{}' (lan9252 or et1100-spi)", name));
}

Expected<PdiSpec, std::string> parse_pdi_spec(std::string_view text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string_view::npos || colon + 1 == text.size()) {
    return fail(fmt::format("'{}': expected CHIP:SPIDEV, e.g. lan9252:/dev/spidev0.0", text));
  }
  auto chip = parse_spi_chip(text.substr(0, colon));
  if (!chip) return fail(chip.error());
  return PdiSpec{*chip, std::string(text.substr(colon + 1))};
}

}  // namespace ecat::pdi_spi
