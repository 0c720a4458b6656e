// SII EEPROM parser (ETG.2010; sii-eeprom.md §1-§3): decodes the fixed words
// and every category of an image through the bounds-checked reader. Bad input
// gives a message naming the word address, never a crash.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "common/expected.hpp"
#include "esi/sii_image.hpp"

namespace ecat::esi {

Expected<SiiImage, std::string> parse_sii(std::span<const std::uint8_t> bytes);

}  // namespace ecat::esi
