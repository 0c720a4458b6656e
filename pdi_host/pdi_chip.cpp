#include "pdi_host/pdi_chip.hpp"

namespace ecat::pdi_host {

Expected<PdiChip, std::string> parse_pdi_chip(std::string_view text) {
  if (text == "direct") return PdiChip::Direct;
  if (text == "lan9252") return PdiChip::Lan9252;
  if (text == "et1100-spi") return PdiChip::Et1100Spi;
  return fail("--pdi-chip " + std::string(text) + ": expected direct, lan9252 or et1100-spi");
}

const char* describe(PdiChip chip) noexcept {
  switch (chip) {
    case PdiChip::Direct: return "direct";
    case PdiChip::Lan9252: return "lan9252";
    case PdiChip::Et1100Spi: return "et1100-spi";
  }
  return "?";
}

}  // namespace ecat::pdi_host
