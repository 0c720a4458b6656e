// SII EEPROM layout constants (ETG.1000.6 §5.4, ETG.2010; shared/spec/sii-eeprom.md
// §1-§3): word addresses of the fixed area, category type codes and the bit
// layouts of the fields the writer and the parser share.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ecat::esi::sii {

// --- fixed area, word addresses (sii-eeprom.md §1) ---
inline constexpr std::size_t kWordPdiControl = 0x0000;
inline constexpr std::size_t kWordPdiConfiguration = 0x0001;
inline constexpr std::size_t kWordSyncImpulseLength = 0x0002;
inline constexpr std::size_t kWordPdiConfiguration2 = 0x0003;
inline constexpr std::size_t kWordStationAlias = 0x0004;
inline constexpr std::size_t kWordChecksum = 0x0007;
inline constexpr std::size_t kWordVendorId = 0x0008;
inline constexpr std::size_t kWordProductCode = 0x000A;
inline constexpr std::size_t kWordRevision = 0x000C;
inline constexpr std::size_t kWordSerial = 0x000E;
inline constexpr std::size_t kWordExecutionDelay = 0x0010;
inline constexpr std::size_t kWordPort0Delay = 0x0011;
inline constexpr std::size_t kWordPort1Delay = 0x0012;
inline constexpr std::size_t kWordBootstrapRxOffset = 0x0014;
inline constexpr std::size_t kWordStandardRxOffset = 0x0018;
inline constexpr std::size_t kWordMailboxProtocols = 0x001C;
inline constexpr std::size_t kWordSize = 0x003E;
inline constexpr std::size_t kWordVersion = 0x003F;
inline constexpr std::size_t kWordFirstCategory = 0x0040;

inline constexpr std::size_t kConfigAreaCrcBytes = 14;  // CRC over bytes 0..13
inline constexpr std::size_t kFixedAreaBytes = kWordFirstCategory * 2;
inline constexpr std::uint16_t kVersion = 1;
// Word 3Eh holds the EEPROM size in Kbit minus one (= bytes / 128 - 1).
inline constexpr std::size_t kBytesPerSizeUnit = 128;
inline constexpr std::uint16_t kChecksumDisabled = 0x88A4;  // debug value, check skipped

// --- word 1Ch mailbox protocols ---
inline constexpr std::uint16_t kProtoAoE = 1u << 0;
inline constexpr std::uint16_t kProtoEoE = 1u << 1;
inline constexpr std::uint16_t kProtoCoE = 1u << 2;
inline constexpr std::uint16_t kProtoFoE = 1u << 3;
inline constexpr std::uint16_t kProtoSoE = 1u << 4;
inline constexpr std::uint16_t kProtoVoE = 1u << 5;

// --- category types (sii-eeprom.md §3) ---
enum class CategoryType : std::uint16_t {
  Nop = 0,
  Strings = 10,
  DataTypes = 20,
  General = 30,
  Fmmu = 40,
  SyncM = 41,
  FmmuEx = 42,
  SyncUnit = 43,
  TxPdo = 50,
  RxPdo = 51,
  Dc = 60,
  End = 0xFFFF,
};
inline constexpr std::size_t kCategoryHeaderBytes = 4;  // type word + length word

// --- GENERAL (30), 32 bytes ---
inline constexpr std::size_t kGeneralBytes = 32;
inline constexpr std::uint8_t kCoeEnableSdo = 1u << 0;
inline constexpr std::uint8_t kCoeSdoInfo = 1u << 1;
inline constexpr std::uint8_t kCoePdoAssign = 1u << 2;
inline constexpr std::uint8_t kCoePdoConfig = 1u << 3;
inline constexpr std::uint8_t kCoePdoUpload = 1u << 4;
inline constexpr std::uint8_t kCoeCompleteAccess = 1u << 5;
inline constexpr std::uint8_t kFoeEnable = 1u << 0;
inline constexpr std::uint8_t kEoeEnable = 1u << 0;
inline constexpr std::uint8_t kFlagEnableSafeOp = 1u << 0;
inline constexpr std::uint8_t kFlagNotLrw = 1u << 1;
inline constexpr std::uint8_t kFlagMboxDataLinkLayer = 1u << 2;
inline constexpr std::uint8_t kFlagIdentAlStatus = 1u << 3;
inline constexpr std::uint8_t kFlagIdentPhysicalMemory = 1u << 4;
// Physical port nibbles (4 bits per port, port 0 in bits 3:0).
inline constexpr std::uint16_t kPortNotUsed = 0x0;
inline constexpr std::uint16_t kPortMii = 0x1;
inline constexpr std::uint16_t kPortEbus = 0x3;
inline constexpr std::uint16_t kPortFastHotConnect = 0x4;

// --- FMMU (40): one byte per FMMU ---
inline constexpr std::uint8_t kFmmuUnused = 0x00;
inline constexpr std::uint8_t kFmmuOutputs = 0x01;
inline constexpr std::uint8_t kFmmuInputs = 0x02;
inline constexpr std::uint8_t kFmmuSyncMStatus = 0x03;
inline constexpr std::uint8_t kFmmuPad = 0xFF;

// --- SYNCM (41), 8 bytes per SM ---
inline constexpr std::size_t kSyncManagerBytes = 8;
inline constexpr std::uint8_t kSmEnable = 1u << 0;
inline constexpr std::uint8_t kSmFixedContent = 1u << 1;
inline constexpr std::uint8_t kSmVirtual = 1u << 2;
inline constexpr std::uint8_t kSmOpOnly = 1u << 3;

// --- TXPDO (50) / RXPDO (51) ---
inline constexpr std::size_t kPdoHeaderBytes = 8;
inline constexpr std::size_t kPdoEntryBytes = 8;
inline constexpr std::uint16_t kPdoMandatory = 0x0001;
inline constexpr std::uint16_t kPdoDefault = 0x0002;
inline constexpr std::uint16_t kPdoFixed = 0x0010;
inline constexpr std::uint16_t kPdoVirtual = 0x0020;
inline constexpr std::uint8_t kPdoNoSm = 0xFF;  // PDO not assigned by default

// --- DC (60), 24 bytes per op mode ---
inline constexpr std::size_t kDcModeBytes = 24;

inline constexpr std::size_t kMaxStrings = 255;
inline constexpr std::size_t kMaxStringLength = 255;

}  // namespace ecat::esi::sii
