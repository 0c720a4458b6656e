#include "pdi_spi/emulated_et1100_spi.hpp"

#include <algorithm>

#include "pdi_spi/et1100_spi_registers.hpp"

namespace ecat::pdi_spi {

using namespace et1100;

namespace {

constexpr std::uint8_t kAllBits = 0xFF;

// What one access clocked: its MOSI bytes as the chip sampled them (bits
// after the last clock read as 0) and how many bytes were complete.
struct Clocked {
  std::span<const std::uint8_t> tx;
  std::size_t whole;   // bytes with all 8 clocks
  unsigned partial;    // clocks of the last, incomplete byte (0: none)

  std::size_t bytes() const { return tx.size(); }
  std::uint8_t mosi(std::size_t i) const {
    if (i >= tx.size()) return 0;
    if (i < whole) return tx[i];
    return static_cast<std::uint8_t>(tx[i] & ~(kAllBits >> partial));
  }
};

}  // namespace

bool EmulatedEt1100Spi::transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept {
  return transfer_clocks(tx, rx, tx.size() * kBitsPerByte);
}

bool EmulatedEt1100Spi::transfer_clocks(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx,
                                        std::size_t clocks) noexcept {
  count();
  std::fill(rx.begin(), rx.end(), std::uint8_t{0});
  const std::size_t bytes = (clocks + kBitsPerByte - 1) / kBitsPerByte;
  if (rx.size() != tx.size() || tx.size() != bytes) {
    violation();  // the caller's buffers do not match its clock count: no access
    return true;
  }
  const Clocked in{tx, clocks / kBitsPerByte, static_cast<unsigned>(clocks % kBitsPerByte)};
  // Section II §2.9.5.1: bits 2:0 are the access's clock count modulo 8;
  // anything but whole bytes is an interface error by itself.
  auto error = static_cast<std::uint8_t>(clocks % kBitsPerByte);
  if (in.partial != 0) violation();

  auto address = static_cast<std::uint16_t>((in.mosi(0) << kAddressHighShift) | (in.mosi(1) >> kAddressLowShift));
  std::uint8_t command = in.mosi(1) & kCommandMask;
  std::size_t phase = 2;
  if (command == kCmdAddressExtension) {
    address = static_cast<std::uint16_t>(address |
                                         ((in.mosi(2) >> kExtensionByteAddressShift) << kExtensionAddressShift));
    command = (in.mosi(2) >> kExtensionCommandShift) & kCommandMask;
    phase = 3;
  }
  // Address phase: the AL event request, least significant byte first.
  std::uint8_t al[4];
  esc_.read(kAlEventRequest, al);
  std::copy_n(al, std::min(phase, bytes), rx.begin());

  if (in.whole < phase) {
    violation();  // the access ended inside the address phase: nothing is accessed
  } else {
    std::size_t data = phase;
    switch (command) {
      case kCmdNop:
        break;
      case kCmdReadWaitState:
        if (data < bytes) {
          if (in.mosi(data) != kWaitStateByte) violation();
          rx[data] = kWaitStateByte;  // MISO during the wait state: undefined, 0xFF here
        }
        ++data;
        [[fallthrough]];
      case kCmdRead: {
        if (data >= bytes) break;  // no data phase: a read of 0 bytes
        // The byte clocked with MOSI = 0xFF is the last one read; the ESC
        // prefetches nothing beyond it (so an SM buffer is not touched).
        std::size_t end = data;
        while (end < bytes && in.mosi(end) != kReadTermination) {
          if (in.mosi(end) != kReadNext) violation();
          ++end;
        }
        if (end == bytes) {
          violation();  // not terminated: read what was clocked
          error |= kPdiErrorReadTerminationMissing;
        } else {
          ++end;
          if (end != bytes) {
            violation();
            error |= kPdiErrorAccessAfterTermination;
          }
        }
        esc_.read(address, rx.subspan(data, end - data));
        break;
      }
      case kCmdWrite:
        // Only whole bytes are written: the bits of an incomplete last byte
        // are not a byte of data.
        esc_.write(address, tx.subspan(data, in.whole - data));
        break;
      default:
        violation();  // reserved command: no access (not a PDI error reason in Section II)
        break;
    }
  }
  if (error != 0) {
    esc_.count_pdi_error(static_cast<std::uint8_t>(error | (((command >> 1) & kPdiErrorCommandBits)
                                                            << kPdiErrorCommandShift)));
  }
  return true;
}

}  // namespace ecat::pdi_spi
