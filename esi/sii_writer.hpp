// SII EEPROM image writer (ETG.2010; shared/spec/sii-eeprom.md §4-§5): turns a
// device description into the decoded image, and an image into the bytes an
// EEPROM holds. Category order: STRINGS, GENERAL, FMMU, SYNCM, TXPDO, RXPDO,
// DC, any raw categories, END; the rest of the EEPROM is 0xFF.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/expected.hpp"
#include "esi/sii_image.hpp"
#include "od/device.hpp"

namespace ecat::esi {

// Words 0..6 (14 bytes) of the configuration area from the ESC properties;
// the same bytes appear as the ESI's Eeprom/ConfigData.
std::array<std::uint8_t, 14> sii_config_bytes(const od::EscProperties& esc);

// The decoded image of a device (strings collected and indexed here).
SiiImage sii_from_device(const od::DeviceDescription& device);

// Encodes an image into an EEPROM of eeprom_bytes bytes (a multiple of 128).
// The size word is taken from eeprom_bytes and the CRC is computed, so the
// image's size_word/checksum_ok fields are not used. Fails when the contents
// do not fit or the size is not encodable.
Expected<std::vector<std::uint8_t>, std::string> encode_sii(const SiiImage& image,
                                                            std::size_t eeprom_bytes);

// sii_from_device + encode_sii with the device's EEPROM size.
Expected<std::vector<std::uint8_t>, std::string> write_sii(const od::DeviceDescription& device);

}  // namespace ecat::esi
