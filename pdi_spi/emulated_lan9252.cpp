#include "pdi_spi/emulated_lan9252.hpp"

#include <algorithm>

#include "common/le.hpp"
#include "pdi_spi/lan9252_registers.hpp"

namespace ecat::pdi_spi {

using namespace lan9252;

namespace {

constexpr std::uint32_t kIrqCfgInt = 1u << 12;  // IRQ_CFG.IRQ_INT: an enabled interrupt is pending
constexpr unsigned kBitsPerByte = 8;
constexpr std::uint16_t kDwordMask = 0xFFFC;  // the DWORD holding a byte address
constexpr std::uint32_t kByteMask = 0xFF;

bool in_read_fifo(std::uint16_t a) { return a < kPramReadFifo + kFifoPortSize; }
bool in_write_fifo(std::uint16_t a) { return a >= kPramWriteFifo && a < kPramWriteFifo + kFifoPortSize; }

std::size_t whole_dwords(std::size_t lead, std::size_t length) { return (lead + length + kDword - 1) / kDword * kDword; }

}  // namespace

std::uint32_t EmulatedLan9252::int_status() const noexcept { return esc_.irq() ? kIntEcat : 0; }

bool EmulatedLan9252::irq_pin() const noexcept {
  return (irq_cfg_ & kIrqCfgEnable) != 0 && (int_status() & int_en_) != 0;
}

std::uint32_t EmulatedLan9252::pram_command(const Pram& p) const noexcept {
  if (!p.active) return 0;
  const std::size_t left = (p.total - p.position + kDword - 1) / kDword;
  const auto count = static_cast<std::uint32_t>(std::min<std::size_t>(left, kPramFifoDwords));
  return kPramBusy | (count << kPramCountShift) | kPramAvailable;
}

std::uint32_t EmulatedLan9252::read_register(std::uint16_t a) noexcept {
  switch (a) {
    case kIdRev: return kIdRevValue;
    case kIrqCfg: return irq_cfg_ | (irq_pin() ? kIrqCfgInt : 0);
    case kIntSts: return int_status();
    case kIntEn: return int_en_;
    case kByteTest: return kByteTestValue;
    case kHwCfg: return kHwCfgReady;
    case kCsrData: return csr_data_;
    case kCsrCmd: return csr_cmd_;
    case kPramRdAddrLen: return rd_.addr_len;
    case kPramRdCmd: return pram_command(rd_);
    case kPramWrAddrLen: return wr_.addr_len;
    case kPramWrCmd: return pram_command(wr_);
    default: return 0;
  }
}

// Registers are 32 bits wide; a command register acts when its most
// significant byte (the one holding the busy/start bit) is written.
void EmulatedLan9252::write_register_byte(std::uint16_t a, std::uint8_t value) noexcept {
  const std::uint16_t reg = a & kDwordMask;
  const unsigned shift = (a % kDword) * kBitsPerByte;
  const auto put = [&](std::uint32_t& r) { r = (r & ~(kByteMask << shift)) | (std::uint32_t{value} << shift); };
  const bool last = a % kDword == kDword - 1;
  switch (reg) {
    case kIrqCfg: put(irq_cfg_); break;
    case kIntEn: put(int_en_); break;
    case kCsrData: put(csr_data_); break;
    case kCsrCmd:
      put(csr_cmd_);
      if (last && (csr_cmd_ & kCsrBusy) != 0) csr_command();
      break;
    case kPramRdAddrLen: put(rd_.addr_len); break;
    case kPramWrAddrLen: put(wr_.addr_len); break;
    case kPramRdCmd:
      put(rd_cmd_);
      if (last && (rd_cmd_ & kPramAbort) != 0) rd_.active = false;
      else if (last && (rd_cmd_ & kPramBusy) != 0) pram_read_start();
      break;
    case kPramWrCmd:
      put(wr_cmd_);
      if (last && (wr_cmd_ & kPramAbort) != 0) wr_.active = false;
      else if (last && (wr_cmd_ & kPramBusy) != 0) pram_write_start();
      break;
    default: break;  // read-only or not emulated
  }
}

// CSR_SIZE 1, 2 or 4 at a naturally aligned address; the data sits in the
// low bytes of ECAT_CSR_DATA.
void EmulatedLan9252::csr_command() noexcept {
  const std::uint32_t size = (csr_cmd_ & kCsrSizeMask) >> kCsrSizeShift;
  const auto address = static_cast<std::uint16_t>(csr_cmd_ & kCsrAddrMask);
  csr_cmd_ &= ~kCsrBusy;
  if ((size != 1 && size != 2 && size != 4) || address % size != 0 || address >= kProcessRamStart) {
    violation();
    return;
  }
  std::uint8_t b[kDword]{};
  if ((csr_cmd_ & kCsrRead) != 0) {
    esc_.read(address, std::span(b, size));
    csr_data_ = load_le<std::uint32_t>(b);
  } else {
    store_le(b, csr_data_);
    esc_.write(address, std::span<const std::uint8_t>(b, size));
  }
}

void EmulatedLan9252::pram_read_start() noexcept {
  rd_cmd_ &= ~kPramBusy;
  const auto address = static_cast<std::uint16_t>(rd_.addr_len & kPramAddrMask);
  const std::size_t length = rd_.addr_len >> kPramLenShift;
  const std::size_t lead = address % kDword;
  rd_.total = whole_dwords(lead, length);
  rd_.position = 0;
  rd_.active = length > 0;
  std::fill_n(rd_.data.begin(), rd_.total, std::uint8_t{0});
  // The whole range is fetched from the ESC now: the SM rules (last byte
  // releases the buffer) see one read, as from the chip's prefetch.
  esc_.read(address, std::span(rd_.data).subspan(lead, length));
}

void EmulatedLan9252::pram_write_start() noexcept {
  wr_cmd_ &= ~kPramBusy;
  const auto address = static_cast<std::uint16_t>(wr_.addr_len & kPramAddrMask);
  const std::size_t length = wr_.addr_len >> kPramLenShift;
  wr_.total = whole_dwords(address % kDword, length);
  wr_.position = 0;
  wr_.active = length > 0;
}

std::uint8_t EmulatedLan9252::fifo_pop() noexcept {
  if (!rd_.active) {
    violation();  // FIFO read with no PRAM read command
    return 0;
  }
  const std::uint8_t v = rd_.data[rd_.position++];
  if (rd_.position == rd_.total) rd_.active = false;
  return v;
}

void EmulatedLan9252::fifo_push(std::uint8_t value) noexcept {
  if (!wr_.active) {
    violation();  // FIFO write with no PRAM write command
    return;
  }
  wr_.data[wr_.position++] = value;
  if (wr_.position < wr_.total) return;
  wr_.active = false;
  const auto address = static_cast<std::uint16_t>(wr_.addr_len & kPramAddrMask);
  const std::size_t length = wr_.addr_len >> kPramLenShift;
  esc_.write(address, std::span<const std::uint8_t>(wr_.data).subspan(address % kDword, length));
}

bool EmulatedLan9252::transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept {
  count();
  std::fill(rx.begin(), rx.end(), std::uint8_t{0});
  if (tx.size() < kInstrHeader || rx.size() != tx.size()) {
    violation();
    return true;
  }
  const auto address = static_cast<std::uint16_t>((tx[1] << kBitsPerByte) | tx[2]);
  switch (tx[0]) {
    case kInstrRead:
    case kInstrFastRead: {
      const std::size_t first = kInstrHeader + (tx[0] == kInstrFastRead ? kFastReadDummyBytes : 0);
      std::uint32_t latch = 0;
      for (std::size_t i = first; i < tx.size(); ++i) {
        const auto a = static_cast<std::uint16_t>(address + (i - first));
        // Bursts on the FIFO data port stay on the FIFO.
        if (in_read_fifo(address)) {
          rx[i] = fifo_pop();
          continue;
        }
        if (i == first || a % kDword == 0) latch = read_register(a & kDwordMask);
        rx[i] = static_cast<std::uint8_t>(latch >> ((a % kDword) * kBitsPerByte));
      }
      return true;
    }
    case kInstrWrite:
      for (std::size_t i = kInstrHeader; i < tx.size(); ++i) {
        if (in_write_fifo(address)) {
          fifo_push(tx[i]);
        } else {
          write_register_byte(static_cast<std::uint16_t>(address + (i - kInstrHeader)), tx[i]);
        }
      }
      return true;
    default:
      violation();  // instruction not emulated (SQI, dual/quad, ...)
      return true;
  }
}

}  // namespace ecat::pdi_spi
