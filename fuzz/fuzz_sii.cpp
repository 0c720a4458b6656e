// libFuzzer target: the SII EEPROM parser (esi/sii_parser.hpp) on arbitrary
// bytes. It must return an image or a message, never crash or read out of
// bounds.
#include <cstdint>
#include <span>

#include "esi/sii_parser.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto image = ecat::esi::parse_sii(std::span(data, size));
  if (!image && image.error().empty()) __builtin_trap();  // errors must say why
  return 0;
}
