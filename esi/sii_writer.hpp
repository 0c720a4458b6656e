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

// How much of the device goes into the image. A small EEPROM (some ESCs have
// 256 bytes) cannot hold every PDO entry name; the writer then falls back step
// by step. Masters that support CoE read the PDOs over SDO anyway.
enum class SiiDetail : std::uint8_t {
  Full,           // every category and every string
  NoEntryNames,   // PDO entries without name strings
  NoPdoDc,        // no TXPDO/RXPDO/DC categories (and none of their strings)
};
const char* to_string(SiiDetail detail) noexcept;

// The decoded image of a device (strings collected and indexed here).
SiiImage sii_from_device(const od::DeviceDescription& device,
                         SiiDetail detail = SiiDetail::Full);

// Encodes an image into an EEPROM of eeprom_bytes bytes (a multiple of 128).
// The size word is taken from eeprom_bytes and the CRC is computed, so the
// image's size_word/checksum_ok fields are not used. Fails when the contents
// do not fit or the size is not encodable.
Expected<std::vector<std::uint8_t>, std::string> encode_sii(const SiiImage& image,
                                                            std::size_t eeprom_bytes);

struct SiiOutput {
  std::vector<std::uint8_t> bytes;
  SiiDetail detail = SiiDetail::Full;  // the most detailed level that fits
};
// sii_from_device + encode_sii with the device's EEPROM size, at the most
// detailed level that fits; an error if not even NoPdoDc fits.
Expected<SiiOutput, std::string> write_sii_detailed(const od::DeviceDescription& device);
// The same, bytes only.
Expected<std::vector<std::uint8_t>, std::string> write_sii(const od::DeviceDescription& device);

}  // namespace ecat::esi
