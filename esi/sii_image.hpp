// The decoded contents of an SII EEPROM (ETG.2010; sii-eeprom.md): the fixed
// words 0..3Fh and every category, as plain values. The writer builds one from
// a device description and encodes it; the parser decodes bytes back into one,
// so parse_sii(encode_sii(x)) == x. The ESC emulator and the master read it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "esi/sii_layout.hpp"

namespace ecat::esi {

// Words 0..6: copied by the ESC into its registers at power-on.
struct SiiConfigArea {
  std::uint16_t pdi_control = 0;          // word 0 -> 0x0140/0x0141
  std::uint16_t pdi_configuration = 0;    // word 1 -> 0x0150/0x0151
  std::uint16_t sync_impulse_length = 0;  // word 2 -> 0x0982 (10 ns units)
  std::uint16_t pdi_configuration2 = 0;   // word 3 -> 0x0152/0x0153
  std::uint16_t station_alias = 0;        // word 4 -> 0x0012
  std::uint16_t reserved5 = 0;
  std::uint16_t reserved6 = 0;
  friend bool operator==(const SiiConfigArea&, const SiiConfigArea&) = default;
};

struct SiiMailboxArea {
  std::uint16_t receive_offset = 0;  // master -> slave (SM0)
  std::uint16_t receive_size = 0;
  std::uint16_t send_offset = 0;  // slave -> master (SM1)
  std::uint16_t send_size = 0;
  friend bool operator==(const SiiMailboxArea&, const SiiMailboxArea&) = default;
};

// GENERAL category (30); string fields are 1-based indices into strings (0 = none).
struct SiiGeneral {
  std::uint8_t group_idx = 0;
  std::uint8_t image_idx = 0;
  std::uint8_t order_idx = 0;
  std::uint8_t name_idx = 0;
  std::uint8_t reserved4 = 0;
  std::uint8_t coe_details = 0;
  std::uint8_t foe_details = 0;
  std::uint8_t eoe_details = 0;
  std::uint8_t soe_channels = 0;
  std::uint8_t ds402_channels = 0;
  std::uint8_t sysman_class = 0;
  std::uint8_t flags = 0;
  std::int16_t current_on_ebus_ma = 0;
  std::uint8_t group_idx2 = 0;
  std::uint8_t reserved15 = 0;
  std::uint16_t physical_ports = 0;
  std::uint16_t physical_memory_address = 0;
  friend bool operator==(const SiiGeneral&, const SiiGeneral&) = default;
};

// SYNCM category (41), one per sync manager.
struct SiiSyncManager {
  std::uint16_t start_address = 0;
  std::uint16_t length = 0;
  std::uint8_t control = 0;
  std::uint8_t status = 0;
  std::uint8_t enable = 0;  // sii::kSmEnable | kSmFixedContent | ...
  std::uint8_t type = 0;    // 0 unused, 1 MBoxOut, 2 MBoxIn, 3 Outputs, 4 Inputs
  friend bool operator==(const SiiSyncManager&, const SiiSyncManager&) = default;
};

struct SiiPdoEntry {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t name_idx = 0;
  std::uint8_t data_type = 0;  // low byte of the CoE data type code
  std::uint8_t bit_length = 0;
  std::uint16_t flags = 0;
  friend bool operator==(const SiiPdoEntry&, const SiiPdoEntry&) = default;
};

// TXPDO (50) / RXPDO (51).
struct SiiPdo {
  std::uint16_t index = 0;
  std::uint8_t sync_manager = 0;
  std::uint8_t synchronization = 0;
  std::uint8_t name_idx = 0;
  std::uint16_t flags = 0;
  std::vector<SiiPdoEntry> entries;
  friend bool operator==(const SiiPdo&, const SiiPdo&) = default;
};

// DC category (60), 24 bytes per op mode.
struct SiiDcMode {
  std::uint32_t cycle_time_sync0 = 0;
  std::uint32_t shift_time_sync0 = 0;
  std::uint32_t shift_time_sync1 = 0;
  std::int16_t cycle_time_sync1_factor = 0;
  std::uint16_t assign_activate = 0;
  std::int16_t cycle_time_sync0_factor = 0;
  std::uint8_t name_idx = 0;
  std::uint8_t desc_idx = 0;
  std::array<std::uint8_t, 4> reserved{};
  friend bool operator==(const SiiDcMode&, const SiiDcMode&) = default;
};

// A category the parser does not decode (kept raw so nothing is lost).
struct SiiRawCategory {
  std::uint16_t type = 0;
  std::vector<std::uint8_t> data;  // whole words
  friend bool operator==(const SiiRawCategory&, const SiiRawCategory&) = default;
};

struct SiiImage {
  SiiConfigArea config;
  bool checksum_ok = true;  // parser: stored CRC matched (or the debug value 0x88A4)
  std::uint32_t vendor_id = 0;
  std::uint32_t product_code = 0;
  std::uint32_t revision = 0;
  std::uint32_t serial = 0;
  std::uint16_t execution_delay = 0;
  std::uint16_t port0_delay = 0;
  std::uint16_t port1_delay = 0;
  SiiMailboxArea bootstrap_mailbox;
  SiiMailboxArea standard_mailbox;
  std::uint16_t mailbox_protocols = 0;  // sii::kProtoCoE | ...
  std::uint16_t size_word = 0;          // EEPROM size in Kbit - 1
  std::uint16_t version = 0;

  // Categories. Strings are 1-based: strings[0] is string index 1.
  std::vector<std::string> strings;
  std::optional<SiiGeneral> general;
  std::vector<std::uint8_t> fmmus;  // one usage code per FMMU, padding dropped
  std::vector<SiiSyncManager> sync_managers;
  std::vector<SiiPdo> tx_pdos;
  std::vector<SiiPdo> rx_pdos;
  std::vector<SiiDcMode> dc_modes;
  std::vector<SiiRawCategory> other_categories;

  // EEPROM size in bytes that the size word announces.
  std::size_t eeprom_bytes() const noexcept { return (std::size_t{size_word} + 1) * sii::kBytesPerSizeUnit; }
  // The string with 1-based index idx, or "" for 0 / out of range.
  std::string string_at(std::uint8_t idx) const {
    return (idx == 0 || idx > strings.size()) ? std::string{} : strings[idx - 1u];
  }
  friend bool operator==(const SiiImage&, const SiiImage&) = default;
};

}  // namespace ecat::esi
