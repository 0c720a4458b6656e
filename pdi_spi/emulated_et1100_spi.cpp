#include "pdi_spi/emulated_et1100_spi.hpp"

#include <algorithm>

#include "pdi_spi/et1100_spi_registers.hpp"

namespace ecat::pdi_spi {

using namespace et1100;

bool EmulatedEt1100Spi::transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept {
  count();
  std::fill(rx.begin(), rx.end(), std::uint8_t{0});
  if (tx.size() < 2 || rx.size() != tx.size()) {
    violation();
    return true;  // the chip sees a runt access and does nothing
  }
  auto address = static_cast<std::uint16_t>((tx[0] << kAddressHighShift) | (tx[1] >> kAddressLowShift));
  std::uint8_t command = tx[1] & kCommandMask;
  std::size_t phase = 2;
  if (command == kCmdAddressExtension) {
    if (tx.size() < 3) {
      violation();
      return true;
    }
    address = static_cast<std::uint16_t>(address | ((tx[2] >> kExtensionByteAddressShift) << kExtensionAddressShift));
    command = (tx[2] >> kExtensionCommandShift) & kCommandMask;
    phase = 3;
  }
  // Address phase: the AL event request, least significant byte first.
  std::uint8_t al[4];
  esc_.read(kAlEventRequest, al);
  std::copy_n(al, phase, rx.begin());

  std::size_t data = phase;
  switch (command) {
    case kCmdNop:
      return true;
    case kCmdReadWaitState:
      if (data >= tx.size() || tx[data] != kWaitStateByte) violation();
      if (data < rx.size()) rx[data] = kWaitStateByte;  // MISO during the wait state: undefined, 0xFF here
      ++data;
      [[fallthrough]];
    case kCmdRead: {
      if (data >= tx.size()) return true;
      // The byte clocked with MOSI = 0xFF is the last one read; the ESC
      // prefetches nothing beyond it (so an SM buffer is not touched).
      std::size_t end = data;
      while (end < tx.size() && tx[end] != kReadTermination) {
        if (tx[end] != kReadNext) violation();
        ++end;
      }
      if (end == tx.size()) {
        violation();  // not terminated: read what was clocked
      } else {
        ++end;
        if (end != tx.size()) violation();  // bytes clocked after the termination
      }
      esc_.read(address, rx.subspan(data, end - data));
      return true;
    }
    case kCmdWrite:
      esc_.write(address, tx.subspan(data));
      return true;
    default:
      violation();  // reserved command
      return true;
  }
}

}  // namespace ecat::pdi_spi
