// A device description built from what a master reads off a live slave
// (`ecat-master --capture`, docs/twins.md "Capturing a twin from a live
// network"): the SII image, the ESC's feature registers 0x0000-0x000F and,
// for a CoE slave with SDO information, the dictionary as SDO information
// describes it with the values uploaded. Pure values in, a model and notes
// out: the master side (apps/ecat-master/capture_*.cpp) does the reading,
// this file decides what the device file says, so it can be tested on exact
// inputs. Whatever cannot be represented or is missing becomes a note, never
// an error, unless not even the SII can be parsed.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/expected.hpp"
#include "od/device.hpp"

namespace ecat::esi {

// ESC information registers 0x0000-0x000F (ESC datasheet Section II).
inline constexpr std::size_t kEscInfoBytes = 16;
// The most of an SII a capture reads (a size word may announce up to 8 MiB):
// 64 KiB, 512 Kbit, more than any EEPROM an ESC is specified for.
inline constexpr std::size_t kCaptureMaxSiiBytes = 0x10000;

// One entry as Get Entry Description returned it, with its uploaded value.
struct CapturedEntry {
  std::uint8_t subindex = 0;
  std::uint16_t data_type = 0;
  std::uint16_t bit_length = 0;
  std::uint16_t access = 0;  // ObjAccess word (od::Access bits)
  std::string name;
  std::optional<std::vector<std::uint8_t>> value;  // none: not readable or the upload failed
};

// One object as Get Object Description returned it, and its entries.
struct CapturedObject {
  std::uint16_t index = 0;
  std::uint16_t data_type = 0;
  std::uint8_t max_subindex = 0;
  std::uint8_t object_code = 0;  // 7 VAR, 8 ARRAY, 9 RECORD
  std::string name;
  std::vector<CapturedEntry> entries;  // in subindex order, those described
};

struct CaptureInput {
  std::vector<std::uint8_t> sii;                    // the image as read
  std::array<std::uint8_t, kEscInfoBytes> esc_info{};  // 0x0000-0x000F
  // The dictionary through SDO information; empty when the slave has none
  // (then the model comes from the SII alone).
  std::vector<CapturedObject> objects;
  bool dictionary_read = false;  // SDO information answered the OD list
};

struct CaptureResult {
  od::DeviceDescription device;
  std::vector<std::string> notes;  // what is missing or was repaired, one line each
};

Expected<CaptureResult, std::string> device_from_capture(const CaptureInput& input);

// Parts of the conversion, for the tests (capture_sii.cpp, capture_dictionary.cpp).
void apply_esc_registers(const std::array<std::uint8_t, kEscInfoBytes>& regs, od::DeviceDescription& device);
// The objects into the dictionary; PDOs from the mapping objects (16xxh/1Axxh)
// and their SMs from the assignment objects (1C10h+n). Notes per item skipped.
void apply_dictionary(const std::vector<CapturedObject>& objects, od::DeviceDescription& device,
                      std::vector<std::string>& notes);

}  // namespace ecat::esi
