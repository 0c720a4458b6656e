// SII EEPROM interface behaviour (Section I §11.2, Section II 0x0500-0x050F;
// shared/spec/esc-registers.md §9, masters.md §6 #8/#9).
#include "esc/sii_interface.hpp"

#include <algorithm>

#include "common/le.hpp"

namespace ecat::esc {

using namespace sii_bits;

namespace {
constexpr std::uint8_t kCrcPolynomial = 0x07;
constexpr std::uint8_t kCrcInit = 0xFF;
constexpr unsigned kReadWords4 = 2;
constexpr unsigned kReadWords8 = 4;
// 0x0502 bits the ECAT/PDI owner may write: write enable and the command.
constexpr std::uint16_t kControlWritable = kWriteEnable | kCommandMask;
}  // namespace

std::uint8_t sii_crc(std::span<const std::uint8_t> bytes) noexcept {
  std::uint8_t crc = kCrcInit;
  for (std::uint8_t b : bytes) {
    crc = static_cast<std::uint8_t>(crc ^ b);
    for (int i = 0; i < 8; ++i) {
      crc = static_cast<std::uint8_t>((crc & 0x80) ? (crc << 1) ^ kCrcPolynomial : crc << 1);
    }
  }
  return crc;
}

void SiiInterface::bind(std::uint8_t* regs, EscConfig& config) noexcept {
  regs_ = regs;
  config_ = &config;
}

void SiiInterface::reset(bool checksum_ok) noexcept {
  std::fill_n(regs_, sii_reg::kSize, std::uint8_t{0});
  busy_until_.reset();
  pending_ = 0;
  set_checksum_ok(checksum_ok);
}

void SiiInterface::set_checksum_ok(bool ok) noexcept {
  std::uint16_t c = static_cast<std::uint16_t>(control() & ~(kChecksumError | kNotLoaded | kReadSize8));
  if (!ok) c |= kChecksumError | kNotLoaded;
  if (config_->sii_read_8_bytes) c |= kReadSize8;
  set_control(c);
}

std::uint16_t SiiInterface::control() const noexcept {
  return load_le<std::uint16_t>(regs_ + sii_reg::kControlStatus);
}
void SiiInterface::set_control(std::uint16_t v) noexcept { store_le(regs_ + sii_reg::kControlStatus, v); }

bool SiiInterface::pdi_owns() const noexcept {
  return (regs_[sii_reg::kConfiguration] & kOfferToPdi) != 0 &&
         (regs_[sii_reg::kPdiAccessState] & kPdiAccess) != 0;
}

std::uint16_t SiiInterface::word(std::uint32_t address) const noexcept {
  const auto& img = config_->sii;
  const std::size_t at = static_cast<std::size_t>(address) * 2;
  if (at + 2 > img.size()) return 0xFFFF;
  return load_le<std::uint16_t>(img.data() + at);
}

SiiInterface::Action SiiInterface::write(unsigned offset, std::span<const std::uint8_t> in, Side side,
                                         Nanoseconds now) noexcept {
  bool command_written = false;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const unsigned at = offset + static_cast<unsigned>(i);
    if (at >= sii_reg::kSize) break;
    const std::uint8_t v = in[i];
    if (at == sii_reg::kConfiguration) {
      // 0x0500: ECAT only. Bit 1 forces the PDI to give the EEPROM back.
      if (side != Side::Ecat) continue;
      regs_[at] = static_cast<std::uint8_t>(v & kOfferToPdi);
      if (v & kForcePdiRelease) regs_[sii_reg::kPdiAccessState] = 0;
      if ((v & kOfferToPdi) == 0) regs_[sii_reg::kPdiAccessState] = 0;
      continue;
    }
    if (at == sii_reg::kPdiAccessState) {
      // 0x0501: PDI may take/release access only while offered and not forced back.
      if (side == Side::Pdi && (regs_[sii_reg::kConfiguration] & kOfferToPdi)) {
        regs_[at] = static_cast<std::uint8_t>(v & kPdiAccess);
      }
      continue;
    }
    // 0x0502-0x050F belong to whoever owns the interface; ignored while busy.
    const bool owner = (side == Side::Pdi) == pdi_owns();
    if (!owner || (control() & kBusy)) continue;
    if (at == sii_reg::kControlStatus || at == sii_reg::kControlStatus + 1) {
      const std::uint16_t mask = static_cast<std::uint16_t>(kControlWritable >> (8 * (at - sii_reg::kControlStatus)));
      regs_[at] = static_cast<std::uint8_t>((regs_[at] & ~mask) | (v & mask));
      if (at == sii_reg::kControlStatus + 1) command_written = true;
      if (at == sii_reg::kControlStatus) write_enable_ = (v & kWriteEnable) != 0;
      continue;
    }
    regs_[at] = v;  // address 0x0504-0x0507, data 0x0508-0x050F
  }
  if (!command_written) return Action::None;
  // A command is taken when byte 0x0503 is written (after the address bytes
  // of the same access, so a 6-byte write of control+address works).
  const std::uint16_t cmd = control() & kCommandMask;
  if (cmd == kCommandIdle) {
    set_control(static_cast<std::uint16_t>(control() & ~kErrorBits));  // idle clears errors
    return Action::None;
  }
  if (stuck_) {
    pending_ = cmd;  // busy for good: no deadline
    set_control(static_cast<std::uint16_t>(control() | kBusy));
    return Action::None;
  }
  if (config_->sii_busy_time.count() > 0) {
    pending_ = cmd;
    busy_until_ = now + config_->sii_busy_time;
    set_control(static_cast<std::uint16_t>(control() | kBusy));
    return Action::None;
  }
  return execute(cmd);
}

void SiiInterface::set_stuck(bool stuck, Nanoseconds now) noexcept {
  stuck_ = stuck;
  if (!stuck && pending_ != 0 && !busy_until_) busy_until_ = now;
}

SiiInterface::Action SiiInterface::poll(Nanoseconds now) noexcept {
  if (!busy_until_ || now < *busy_until_) return Action::None;
  busy_until_.reset();
  const std::uint16_t cmd = pending_;
  pending_ = 0;
  return execute(cmd);
}

SiiInterface::Action SiiInterface::execute(std::uint16_t cmd) noexcept {
  std::uint16_t c = static_cast<std::uint16_t>(control() & ~(kBusy | kErrorBits | kCommandMask));
  const std::uint32_t address = load_le<std::uint32_t>(regs_ + sii_reg::kAddress);
  Action action = Action::None;
  if (cmd == kCommandRead) {
    const unsigned words = config_->sii_read_8_bytes ? kReadWords8 : kReadWords4;
    for (unsigned w = 0; w < words; ++w) {
      store_le(regs_ + sii_reg::kData + 2 * w, word(address + w));
    }
  } else if (cmd == kCommandWrite) {
    // Write needs the write-enable bit in the same access (Section II 0x0502 bit 0);
    // words beyond the image are not acknowledged (no EEPROM there).
    const std::size_t at = static_cast<std::size_t>(address) * 2;
    if (!write_enable_) {
      c |= kWriteEnableError;
    } else if (at + 2 > config_->sii.size()) {
      c |= kAcknowledgeError;
    } else {
      const std::uint16_t value = load_le<std::uint16_t>(regs_ + sii_reg::kData);
      store_le(config_->sii.mutable_data() + at, value);  // copies a shared image first
      if (config_->sii_write_back) config_->sii_write_back(static_cast<std::uint16_t>(address), value);
    }
  } else if (cmd == kCommandReload) {
    action = Action::Reload;
  } else {
    c |= kAcknowledgeError;  // invalid command
  }
  write_enable_ = false;
  c = static_cast<std::uint16_t>(c & ~kWriteEnable);  // write enable self-clears
  set_control(c);
  return action;
}

}  // namespace ecat::esc
