// The SII EEPROM interface, registers 0x0500-0x050F (ESC datasheet Section I
// §11, Section II 0x0500; shared/spec/esc-registers.md §9), backed by the
// SII image in EscConfig. Ownership ECAT/PDI (0x0500/0x0501), commands read
// (4 or 8 bytes, 0x0502 bit 6), write (one word, needs write enable bit 0)
// and reload, busy on the injected clock, checksum and command error bits.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/clock.hpp"
#include "esc/access_side.hpp"
#include "esc/esc_config.hpp"

namespace ecat::esc {

namespace sii_bits {
// 0x0500 EEPROM configuration.
inline constexpr std::uint8_t kOfferToPdi = 0x01;
inline constexpr std::uint8_t kForcePdiRelease = 0x02;
// 0x0501 EEPROM PDI access state.
inline constexpr std::uint8_t kPdiAccess = 0x01;
// 0x0502-0x0503 control/status (16 bit).
inline constexpr std::uint16_t kWriteEnable = 0x0001;
inline constexpr std::uint16_t kEmulation = 0x0020;
inline constexpr std::uint16_t kReadSize8 = 0x0040;
inline constexpr std::uint16_t kAddressAlgorithm = 0x0080;
inline constexpr std::uint16_t kCommandMask = 0x0700;
inline constexpr std::uint16_t kCommandIdle = 0x0000;
inline constexpr std::uint16_t kCommandRead = 0x0100;
inline constexpr std::uint16_t kCommandWrite = 0x0200;
inline constexpr std::uint16_t kCommandReload = 0x0400;
inline constexpr std::uint16_t kChecksumError = 0x0800;
inline constexpr std::uint16_t kNotLoaded = 0x1000;
inline constexpr std::uint16_t kAcknowledgeError = 0x2000;
inline constexpr std::uint16_t kWriteEnableError = 0x4000;
inline constexpr std::uint16_t kBusy = 0x8000;
inline constexpr std::uint16_t kErrorBits = kAcknowledgeError | kWriteEnableError;
}  // namespace sii_bits

// Offsets of the block relative to 0x0500.
namespace sii_reg {
inline constexpr unsigned kConfiguration = 0x0;
inline constexpr unsigned kPdiAccessState = 0x1;
inline constexpr unsigned kControlStatus = 0x2;
inline constexpr unsigned kAddress = 0x4;
inline constexpr unsigned kData = 0x8;
inline constexpr unsigned kSize = 0x10;
}  // namespace sii_reg

// SII configuration-area checksum: CRC-8 (poly 0x07, init 0xFF) over words
// 0..6, stored in the low byte of word 7 (ETG.1000.6 §5.4; sii-eeprom.md §2).
std::uint8_t sii_crc(std::span<const std::uint8_t> bytes) noexcept;
inline constexpr std::size_t kSiiConfigAreaBytes = 14;
inline constexpr std::uint16_t kSiiChecksumDisabled = 0x88A4;

class SiiInterface {
 public:
  // What the ESC has to do after an access.
  enum class Action : std::uint8_t { None, Reload };

  // `regs` = the 16 register bytes at 0x0500 inside ESC memory.
  void bind(std::uint8_t* regs, EscConfig& config) noexcept;
  // Power-on state; `checksum_ok` is the result of the EEPROM load.
  void reset(bool checksum_ok) noexcept;
  void set_checksum_ok(bool ok) noexcept;

  // A write of `in` at offset `offset` of the block from `side`.
  Action write(unsigned offset, std::span<const std::uint8_t> in, Side side, Nanoseconds now) noexcept;
  // Completes a busy command whose time has come.
  Action poll(Nanoseconds now) noexcept;
  std::optional<Nanoseconds> next_deadline() const noexcept { return busy_until_; }
  // Fault injection (slave::FaultCatalogue sii_busy_stuck): while stuck, a
  // command sets busy (0x0502 bit 15) and never completes, and the
  // interface ignores writes to 0x0502-0x050F as it does while busy. Unstuck
  // at `now`, a command still waiting completes then (its busy time over).
  void set_stuck(bool stuck, Nanoseconds now) noexcept;

  // Word `address` of the image (0xFFFF past its end, as an erased EEPROM).
  std::uint16_t word(std::uint32_t address) const noexcept;
  bool pdi_owns() const noexcept;

 private:
  std::uint16_t control() const noexcept;
  void set_control(std::uint16_t v) noexcept;
  Action execute(std::uint16_t command) noexcept;
  void write_control(std::span<const std::uint8_t> in, unsigned first, unsigned offset, Side side,
                     bool& command_written) noexcept;

  std::uint8_t* regs_ = nullptr;
  EscConfig* config_ = nullptr;
  std::optional<Nanoseconds> busy_until_;
  std::uint16_t pending_ = 0;  // command waiting for the busy time to pass
  bool stuck_ = false;
  bool write_enable_ = false;
};

}  // namespace ecat::esc
