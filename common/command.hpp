// EtherCAT datagram commands (ETG.1000.4 §5.4, Beckhoff ESC datasheet
// Section I Table 7; shared/spec/esc-registers.md §2). Shared by the ESC
// emulator and the master library.
#pragma once

#include <cstdint>
#include <string_view>

namespace ecat {

enum class Command : std::uint8_t {
  Nop = 0,
  Aprd = 1,
  Apwr = 2,
  Aprw = 3,
  Fprd = 4,
  Fpwr = 5,
  Fprw = 6,
  Brd = 7,
  Bwr = 8,
  Brw = 9,
  Lrd = 10,
  Lwr = 11,
  Lrw = 12,
  Armw = 13,
  Frmw = 14,
};

inline constexpr std::uint8_t kLastCommand = static_cast<std::uint8_t>(Command::Frmw);

// How a command selects the slaves it acts on.
enum class Addressing : std::uint8_t { None, AutoIncrement, Configured, Broadcast, Logical };

constexpr Addressing addressing(Command c) noexcept {
  switch (c) {
    case Command::Aprd:
    case Command::Apwr:
    case Command::Aprw:
    case Command::Armw:
      return Addressing::AutoIncrement;
    case Command::Fprd:
    case Command::Fpwr:
    case Command::Fprw:
    case Command::Frmw:
      return Addressing::Configured;
    case Command::Brd:
    case Command::Bwr:
    case Command::Brw:
      return Addressing::Broadcast;
    case Command::Lrd:
    case Command::Lwr:
    case Command::Lrw:
      return Addressing::Logical;
    case Command::Nop:
      break;
  }
  return Addressing::None;
}

// True for commands whose data carries a read result (xRD, xRW, xRMW).
constexpr bool reads(Command c) noexcept {
  switch (c) {
    case Command::Aprd:
    case Command::Aprw:
    case Command::Fprd:
    case Command::Fprw:
    case Command::Brd:
    case Command::Brw:
    case Command::Lrd:
    case Command::Lrw:
    case Command::Armw:
    case Command::Frmw:
      return true;
    default:
      return false;
  }
}

// True for commands that write slave memory (xWR, xRW, and the non-addressed
// side of xRMW).
constexpr bool writes(Command c) noexcept {
  switch (c) {
    case Command::Apwr:
    case Command::Aprw:
    case Command::Fpwr:
    case Command::Fprw:
    case Command::Bwr:
    case Command::Brw:
    case Command::Lwr:
    case Command::Lrw:
    case Command::Armw:
    case Command::Frmw:
      return true;
    default:
      return false;
  }
}

// Read-write commands count +1 for the read and +2 for the write (ETG.1000.4 §5.4.3).
constexpr bool is_read_write(Command c) noexcept {
  return c == Command::Aprw || c == Command::Fprw || c == Command::Brw || c == Command::Lrw;
}

// Slaves increment ADP for these as the frame passes (Section I Table 7).
constexpr bool increments_adp(Command c) noexcept {
  Addressing a = addressing(c);
  return a == Addressing::AutoIncrement || a == Addressing::Broadcast;
}

constexpr bool is_known_command(std::uint8_t code) noexcept { return code <= kLastCommand; }

constexpr std::string_view to_string(Command c) noexcept {
  switch (c) {
    case Command::Nop: return "NOP";
    case Command::Aprd: return "APRD";
    case Command::Apwr: return "APWR";
    case Command::Aprw: return "APRW";
    case Command::Fprd: return "FPRD";
    case Command::Fpwr: return "FPWR";
    case Command::Fprw: return "FPRW";
    case Command::Brd: return "BRD";
    case Command::Bwr: return "BWR";
    case Command::Brw: return "BRW";
    case Command::Lrd: return "LRD";
    case Command::Lwr: return "LWR";
    case Command::Lrw: return "LRW";
    case Command::Armw: return "ARMW";
    case Command::Frmw: return "FRMW";
  }
  return "?";
}

}  // namespace ecat
