// Object access rights, in the bit layout of the SDO information "ObjAccess"
// word (ETG.1000.6 §5.6.3.6.2; shared/spec/coe-mailbox.md §7.3): read and
// write per ESM state, RxPDO/TxPDO mappability, backup and setting flags.
// The SDO server, the SDO information service and the ESI writer all read
// these same bits, so the three cannot disagree.
#pragma once

#include <cstdint>

namespace ecat::od {

enum class EsmState : std::uint8_t { Init = 1, PreOp = 2, Bootstrap = 3, SafeOp = 4, Op = 8 };

struct Access {
  static constexpr std::uint16_t kReadPreOp = 1u << 0;
  static constexpr std::uint16_t kReadSafeOp = 1u << 1;
  static constexpr std::uint16_t kReadOp = 1u << 2;
  static constexpr std::uint16_t kWritePreOp = 1u << 3;
  static constexpr std::uint16_t kWriteSafeOp = 1u << 4;
  static constexpr std::uint16_t kWriteOp = 1u << 5;
  static constexpr std::uint16_t kRxPdoMappable = 1u << 6;
  static constexpr std::uint16_t kTxPdoMappable = 1u << 7;
  static constexpr std::uint16_t kBackup = 1u << 8;
  static constexpr std::uint16_t kSetting = 1u << 9;

  static constexpr std::uint16_t kReadAll = kReadPreOp | kReadSafeOp | kReadOp;
  static constexpr std::uint16_t kWriteAll = kWritePreOp | kWriteSafeOp | kWriteOp;
  static constexpr std::uint16_t kRo = kReadAll;                // 0x0007
  static constexpr std::uint16_t kRw = kReadAll | kWriteAll;    // 0x003F
  static constexpr std::uint16_t kWo = kWriteAll;               // 0x0038

  std::uint16_t bits = kRo;
  // A "const" entry is read-only and never changes; kept apart because the
  // ESI and SDO info show it as ro, but stored-parameter code must skip it.
  bool is_const = false;

  constexpr bool readable() const noexcept { return (bits & kReadAll) != 0; }
  constexpr bool writable() const noexcept { return (bits & kWriteAll) != 0; }
  constexpr bool rx_mappable() const noexcept { return (bits & kRxPdoMappable) != 0; }
  constexpr bool tx_mappable() const noexcept { return (bits & kTxPdoMappable) != 0; }

  // Init has no mailbox, so there is no SDO access to check there;
  // Bootstrap has only FoE. Both answer false.
  constexpr bool readable_in(EsmState s) const noexcept {
    switch (s) {
      case EsmState::PreOp: return bits & kReadPreOp;
      case EsmState::SafeOp: return bits & kReadSafeOp;
      case EsmState::Op: return bits & kReadOp;
      default: return false;
    }
  }
  constexpr bool writable_in(EsmState s) const noexcept {
    switch (s) {
      case EsmState::PreOp: return bits & kWritePreOp;
      case EsmState::SafeOp: return bits & kWriteSafeOp;
      case EsmState::Op: return bits & kWriteOp;
      default: return false;
    }
  }
  friend constexpr bool operator==(const Access&, const Access&) = default;
};

}  // namespace ecat::od
