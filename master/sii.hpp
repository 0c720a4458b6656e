// What the master needs from a slave's SII EEPROM image (ETG.1000.6 §5.4,
// ETG.2010; shared/spec/sii-eeprom.md): the fixed words 0x00-0x3F (identity,
// mailbox layout, protocols) and a category walker from word 0x40 (STRINGS,
// GENERAL, FMMU, SYNCM, TXPDO/RXPDO, DC). The esi/ layer has its own SII
// writer; this is the master's independent reader, so the two check each other.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/expected.hpp"
#include "common/le.hpp"

namespace ecat::master {

namespace sii {
// Word addresses of the fixed area (sii-eeprom.md §1).
inline constexpr std::uint16_t kPdiControl = 0x0000;
inline constexpr std::uint16_t kStationAlias = 0x0004;
inline constexpr std::uint16_t kChecksum = 0x0007;
inline constexpr std::uint16_t kVendorId = 0x0008;
inline constexpr std::uint16_t kProductCode = 0x000A;
inline constexpr std::uint16_t kRevision = 0x000C;
inline constexpr std::uint16_t kSerial = 0x000E;
inline constexpr std::uint16_t kBootRxMailboxOffset = 0x0014;
inline constexpr std::uint16_t kStdRxMailboxOffset = 0x0018;
inline constexpr std::uint16_t kStdRxMailboxSize = 0x0019;
inline constexpr std::uint16_t kStdTxMailboxOffset = 0x001A;
inline constexpr std::uint16_t kStdTxMailboxSize = 0x001B;
inline constexpr std::uint16_t kMailboxProtocols = 0x001C;
inline constexpr std::uint16_t kSize = 0x003E;
inline constexpr std::uint16_t kVersion = 0x003F;
inline constexpr std::uint16_t kFirstCategory = 0x0040;
inline constexpr std::size_t kFixedAreaBytes = 2 * kFirstCategory;
inline constexpr std::size_t kChecksumCoveredBytes = 14;
// The master's reads through 0x0502 (master/sii_access.cpp, sii_scan.cpp).
inline constexpr std::size_t kReadMax = 8;             // bytes per read command (0x0502 bit 6)
inline constexpr std::size_t kMaxImageBytes = 0x10000;  // 32 K words: far beyond any real EEPROM
inline constexpr unsigned kCommandTries = 3;            // SOEM retries a read on ack error
inline constexpr std::uint16_t kCategoryTypeMask = 0x7FFF;  // bit 15: vendor specific

enum class Category : std::uint16_t {
  Nop = 0, Strings = 10, DataTypes = 20, General = 30, Fmmu = 40, SyncM = 41, FmmuX = 42,
  SyncUnit = 43, TxPdo = 50, RxPdo = 51, Dc = 60, End = 0xFFFF,
};
inline constexpr std::size_t kGeneralBytes = 32;  // must be exactly 16 words (IgH)
inline constexpr std::size_t kSyncMEntryBytes = 8;
inline constexpr std::size_t kPdoHeaderBytes = 8;
inline constexpr std::size_t kPdoEntryBytes = 8;
inline constexpr std::size_t kDcEntryBytes = 24;

// Mailbox protocol bits, word 0x1C.
inline constexpr std::uint16_t kProtoAoe = 0x0001;
inline constexpr std::uint16_t kProtoEoe = 0x0002;
inline constexpr std::uint16_t kProtoCoe = 0x0004;
inline constexpr std::uint16_t kProtoFoe = 0x0008;
inline constexpr std::uint16_t kProtoSoe = 0x0010;
inline constexpr std::uint16_t kProtoVoe = 0x0020;

// GENERAL CoE details bits (byte 5).
inline constexpr std::uint8_t kCoeSdo = 0x01;
inline constexpr std::uint8_t kCoeSdoInfo = 0x02;
inline constexpr std::uint8_t kCoePdoAssign = 0x04;
inline constexpr std::uint8_t kCoePdoConfig = 0x08;
inline constexpr std::uint8_t kCoeUploadAtStartup = 0x10;
inline constexpr std::uint8_t kCoeCompleteAccess = 0x20;

// GENERAL flags (byte 11).
inline constexpr std::uint8_t kFlagEnableSafeOp = 0x01;
inline constexpr std::uint8_t kFlagNotLrw = 0x02;

// SYNCM types (byte 7).
inline constexpr std::uint8_t kSmTypeUnused = 0;
inline constexpr std::uint8_t kSmTypeMailboxOut = 1;
inline constexpr std::uint8_t kSmTypeMailboxIn = 2;
inline constexpr std::uint8_t kSmTypeOutputs = 3;
inline constexpr std::uint8_t kSmTypeInputs = 4;

// PDO flags (TXPDO/RXPDO header).
inline constexpr std::uint16_t kPdoMandatory = 0x0001;
inline constexpr std::uint16_t kPdoDefault = 0x0002;
inline constexpr std::uint16_t kPdoFixed = 0x0010;

// FMMU usage codes.
inline constexpr std::uint8_t kFmmuOutputs = 1;
inline constexpr std::uint8_t kFmmuInputs = 2;
inline constexpr std::uint8_t kFmmuSyncMStatus = 3;

// CRC-8 (poly 0x07, init 0xFF) over the configuration area (sii-eeprom.md §2).
std::uint8_t config_crc(ConstBytes first14) noexcept;
}  // namespace sii

enum class SiiParseError : std::uint8_t {
  TooShort = 1,          // fewer than the 64 fixed words
  CategoryBeyondEnd,     // a category's length runs past the image
  NoEndMarker,           // walk ended without 0xFFFF
  BadGeneralSize,        // GENERAL not 16 words
  BadSyncMSize,          // SYNCM length not a multiple of 8 bytes
  BadPdo,                // PDO entries run past the category
  BadStrings,            // string lengths run past the category
  BadDcSize,             // DC length not a multiple of 24 bytes
};

struct SiiGeneral {
  std::uint8_t group_index = 0, image_index = 0, order_index = 0, name_index = 0;
  std::uint8_t coe_details = 0, foe_details = 0, eoe_details = 0, flags = 0;
  std::int16_t ebus_current_ma = 0;
  std::uint16_t physical_ports = 0;
  std::uint16_t physical_memory_address = 0;
};

struct SiiSyncManager {
  std::uint16_t start = 0;
  std::uint16_t length = 0;
  std::uint8_t control = 0;
  std::uint8_t enable = 0;
  std::uint8_t type = 0;
};

struct SiiPdoEntry {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t name_index = 0;
  std::uint8_t data_type = 0;
  std::uint8_t bit_length = 0;
};

struct SiiPdo {
  std::uint16_t index = 0;
  std::uint8_t sync_manager = 0xFF;  // default SM, 0xFF = not assigned
  std::uint8_t name_index = 0;
  std::uint16_t flags = 0;
  std::vector<SiiPdoEntry> entries;
  std::uint32_t bit_length() const noexcept;
};

struct SiiDcMode {
  std::uint32_t cycle_time_sync0 = 0;
  std::uint32_t shift_time_sync0 = 0;
  std::uint32_t shift_time_sync1 = 0;
  std::int16_t sync1_cycle_factor = 0;
  std::uint16_t assign_activate = 0;
  std::int16_t sync0_cycle_factor = 0;
  std::uint8_t name_index = 0;
};

struct SiiInfo {
  std::uint16_t pdi_control = 0;
  std::uint16_t station_alias = 0;
  std::uint8_t checksum = 0;
  bool checksum_ok = false;
  std::uint32_t vendor_id = 0, product_code = 0, revision = 0, serial = 0;
  std::uint16_t boot_rx_offset = 0, boot_rx_size = 0, boot_tx_offset = 0, boot_tx_size = 0;
  std::uint16_t rx_mailbox_offset = 0, rx_mailbox_size = 0;  // SM0: master -> slave
  std::uint16_t tx_mailbox_offset = 0, tx_mailbox_size = 0;  // SM1: slave -> master
  std::uint16_t mailbox_protocols = 0;
  std::uint16_t size_word = 0, version = 0;

  std::vector<std::string> strings;  // strings[0] = index 1
  std::optional<SiiGeneral> general;
  std::vector<std::uint8_t> fmmu_usage;
  std::vector<SiiSyncManager> sync_managers;
  std::vector<SiiPdo> tx_pdos;
  std::vector<SiiPdo> rx_pdos;
  std::vector<SiiDcMode> dc_modes;
  std::vector<std::uint16_t> category_order;  // types in the order found

  bool has_mailbox() const noexcept { return rx_mailbox_size != 0 && tx_mailbox_size != 0; }
  bool has_coe() const noexcept { return has_mailbox() && (mailbox_protocols & sii::kProtoCoe) != 0; }
  // 1-based string index; empty for 0 or out of range.
  std::string string(std::uint8_t index) const;
  std::string device_name() const;
  // Sum of the bit lengths of the PDOs assigned by default to `sm`.
  std::uint32_t default_pdo_bits(bool tx, std::uint8_t sm) const noexcept;
};

// Parses an image that holds at least the fixed area; the category walk stops
// at 0xFFFF. Words past the image end count as missing (error).
Expected<SiiInfo, SiiParseError> parse_sii(ConstBytes image);

// Bytes of the image needed to hold every category: walks the headers only.
// Returns nullopt while `image` is too short to see the end marker.
std::optional<std::size_t> sii_image_length(ConstBytes image) noexcept;

}  // namespace ecat::master
