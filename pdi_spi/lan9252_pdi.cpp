#include "pdi_spi/lan9252_pdi.hpp"

#include <algorithm>
#include <cstring>

#include "common/le.hpp"
#include "pdi_spi/lan9252_registers.hpp"

namespace ecat::pdi_spi {

using namespace lan9252;

std::size_t lan9252_csr_size(std::uint16_t address, std::size_t remaining) noexcept {
  if (address % 4 == 0 && remaining >= 4) return 4;
  if (address % 2 == 0 && remaining >= 2) return 2;
  return 1;
}

bool Lan9252Pdi::spi_read(std::uint16_t address, std::span<std::uint8_t> out) noexcept {
  const std::size_t header = kInstrHeader + (options_.fast_read ? kFastReadDummyBytes : 0);
  const std::size_t n = header + out.size();
  tx_[0] = options_.fast_read ? kInstrFastRead : kInstrRead;
  tx_[1] = static_cast<std::uint8_t>(address >> 8);
  tx_[2] = static_cast<std::uint8_t>(address);
  std::fill(tx_.begin() + kInstrHeader, tx_.begin() + static_cast<std::ptrdiff_t>(n), std::uint8_t{0});
  if (!transact(std::span(tx_).first(n), std::span(rx_).first(n))) {
    std::fill(out.begin(), out.end(), std::uint8_t{0});
    return false;
  }
  std::memcpy(out.data(), rx_.data() + header, out.size());
  return true;
}

bool Lan9252Pdi::spi_write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept {
  const std::size_t n = kInstrHeader + in.size();
  tx_[0] = kInstrWrite;
  tx_[1] = static_cast<std::uint8_t>(address >> 8);
  tx_[2] = static_cast<std::uint8_t>(address);
  std::memcpy(tx_.data() + kInstrHeader, in.data(), in.size());
  return transact(std::span(tx_).first(n), std::span(rx_).first(n));
}

std::uint32_t Lan9252Pdi::read_system(std::uint16_t address) noexcept {
  std::uint8_t b[kDword]{};
  spi_read(address, b);
  return load_le<std::uint32_t>(b);
}

void Lan9252Pdi::write_system(std::uint16_t address, std::uint32_t value) noexcept {
  std::uint8_t b[kDword];
  store_le(b, value);
  spi_write(address, b);
}

bool Lan9252Pdi::poll(std::uint16_t reg, std::uint32_t mask, std::uint32_t want) noexcept {
  for (unsigned i = 0; i < options_.max_polls && !failed(); ++i) {
    if ((read_system(reg) & mask) == want) return true;
  }
  fail_with("LAN9252: busy/available bit did not change (polled too long)");
  return false;
}

bool Lan9252Pdi::init() noexcept {
  constexpr std::uint32_t kWholeRegister = 0xFFFFFFFF;
  if (!poll(kByteTest, kWholeRegister, kByteTestValue)) return false;
  if (!poll(kHwCfg, kHwCfgReady, kHwCfgReady)) return false;
  // ECAT_INT is the only interrupt source; the pin is enabled, push-pull,
  // active low (the EasyCAT and Microchip EVB wiring; IRQ_CFG = 0x101).
  write_system(kIntEn, 0);
  write_system(kIrqCfg, kIrqCfgEnable | kIrqCfgPushPull);
  write_system(kIntEn, kIntEcat);
  return !failed();
}

void Lan9252Pdi::csr_read(std::uint16_t address, std::span<std::uint8_t> out) noexcept {
  std::uint8_t cmd[kDword];
  store_le(cmd, kCsrBusy | kCsrRead | (static_cast<std::uint32_t>(out.size()) << kCsrSizeShift) | address);
  if (!spi_write(kCsrCmd, cmd)) return;
  if (!options_.skip_csr_poll && !poll(kCsrCmd, kCsrBusy, 0)) return;
  std::uint8_t data[kDword]{};
  spi_read(kCsrData, data);
  std::memcpy(out.data(), data, out.size());  // the value sits in the low bytes
}

void Lan9252Pdi::csr_write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept {
  std::uint8_t data[kDword]{};
  std::memcpy(data, in.data(), in.size());
  if (!spi_write(kCsrData, data)) return;
  std::uint8_t cmd[kDword];
  store_le(cmd, kCsrBusy | (static_cast<std::uint32_t>(in.size()) << kCsrSizeShift) | address);
  if (!spi_write(kCsrCmd, cmd)) return;
  poll(kCsrCmd, kCsrBusy, 0);
}

void Lan9252Pdi::pram_start(std::uint16_t addr_len_reg, std::uint16_t address, std::size_t length) noexcept {
  std::uint8_t b[2 * kDword];
  store_le(b, static_cast<std::uint32_t>(length << kPramLenShift) | address);
  store_le(b + kDword, kPramBusy);
  if (options_.burst_setup) {
    spi_write(addr_len_reg, b);
  } else {
    spi_write(addr_len_reg, std::span<const std::uint8_t>(b, kDword));
    spi_write(static_cast<std::uint16_t>(addr_len_reg + kDword), std::span<const std::uint8_t>(b + kDword, kDword));
  }
}

// The FIFO carries whole DWORDs of the ESC's address space: the first
// holds the start address's byte in lane (address & 3), the last is padded
// (DS00001909 PRAM FIFO alignment; Microchip's driver clocks the same pad
// bytes).
void Lan9252Pdi::pram_read(std::uint16_t address, std::span<std::uint8_t> out) noexcept {
  pram_start(kPramRdAddrLen, address, out.size());
  if (!poll(kPramRdCmd, kPramAvailable, kPramAvailable)) return;
  const std::size_t lead = address % kDword;
  const std::size_t total = (lead + out.size() + kDword - 1) / kDword * kDword;
  std::size_t done = 0;  // FIFO bytes clocked so far
  while (done < total && !failed()) {
    const std::size_t n = std::min(total - done, kMaxBurst);
    std::array<std::uint8_t, kMaxBurst> chunk;
    if (!spi_read(kPramReadFifo, std::span(chunk).first(n))) return;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t at = done + i;
      if (at >= lead && at - lead < out.size()) out[at - lead] = chunk[i];
    }
    done += n;
  }
}

void Lan9252Pdi::pram_write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept {
  pram_start(kPramWrAddrLen, address, in.size());
  if (!poll(kPramWrCmd, kPramAvailable, kPramAvailable)) return;
  const std::size_t lead = address % kDword;
  const std::size_t total = (lead + in.size() + kDword - 1) / kDword * kDword;
  std::size_t done = 0;
  while (done < total && !failed()) {
    const std::size_t n = std::min(total - done, kMaxBurst);
    std::array<std::uint8_t, kMaxBurst> chunk{};
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t at = done + i;
      chunk[i] = at >= lead && at - lead < in.size() ? in[at - lead] : 0;
    }
    if (!spi_write(kPramWriteFifo, std::span(chunk).first(n))) return;
    done += n;
  }
}

void Lan9252Pdi::read(std::uint16_t address, std::span<std::uint8_t> out) noexcept {
  std::size_t done = 0;
  while (done < out.size() && !failed()) {
    const auto a = static_cast<std::uint16_t>(address + done);
    const std::size_t left = out.size() - done;
    if (a >= kProcessRamStart) {
      pram_read(a, out.subspan(done));
      done = out.size();
    } else {
      const std::size_t in_regs = std::min<std::size_t>(left, kProcessRamStart - a);
      const std::size_t n = lan9252_csr_size(a, in_regs);
      csr_read(a, out.subspan(done, n));
      done += n;
    }
  }
  if (failed()) std::fill(out.begin(), out.end(), std::uint8_t{0});
}

void Lan9252Pdi::write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept {
  std::size_t done = 0;
  while (done < in.size() && !failed()) {
    const auto a = static_cast<std::uint16_t>(address + done);
    const std::size_t left = in.size() - done;
    if (a >= kProcessRamStart) {
      pram_write(a, in.subspan(done));
      done = in.size();
    } else {
      const std::size_t in_regs = std::min<std::size_t>(left, kProcessRamStart - a);
      const std::size_t n = lan9252_csr_size(a, in_regs);
      csr_write(a, in.subspan(done, n));
      done += n;
    }
  }
}

}  // namespace ecat::pdi_spi
