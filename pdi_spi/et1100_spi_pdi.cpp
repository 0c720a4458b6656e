#include "pdi_spi/et1100_spi_pdi.hpp"

#include <algorithm>

#include "pdi_spi/et1100_spi_registers.hpp"

namespace ecat::pdi_spi {

using namespace et1100;

std::size_t Et1100SpiPdi::address_phase(std::uint16_t address, std::uint8_t command) noexcept {
  tx_[0] = static_cast<std::uint8_t>(address >> kAddressHighShift);
  const auto low = static_cast<std::uint8_t>((address & kAddressLowMask) << kAddressLowShift);
  if (!options_.three_byte_address && address < kTwoByteAddressLimit) {
    tx_[1] = static_cast<std::uint8_t>(low | command);
    return 2;
  }
  tx_[1] = static_cast<std::uint8_t>(low | kCmdAddressExtension);
  tx_[2] = static_cast<std::uint8_t>(((address >> kExtensionAddressShift) << kExtensionByteAddressShift) |
                                     (command << kExtensionCommandShift));
  return 3;
}

std::size_t Et1100SpiPdi::read_once(std::uint16_t address, std::span<std::uint8_t> out,
                                    std::span<std::uint8_t> al_event) noexcept {
  const bool data = !out.empty();
  const std::uint8_t command = !data ? kCmdNop : options_.wait_state ? kCmdReadWaitState : kCmdRead;
  std::size_t n = address_phase(address, command);
  const std::size_t phase = n;
  if (data && options_.wait_state) tx_[n++] = kWaitStateByte;
  const std::size_t first = n;
  for (std::size_t i = 0; i < out.size(); ++i) tx_[n++] = i + 1 == out.size() ? kReadTermination : kReadNext;
  if (!transact(std::span(tx_).first(n), std::span(rx_).first(n))) {
    std::fill(out.begin(), out.end(), std::uint8_t{0});
    return 0;
  }
  last_al_event_ = static_cast<std::uint16_t>(rx_[0] | (rx_[1] << 8));
  const std::size_t carried = std::min(phase, al_event.size());
  std::copy_n(rx_.begin(), carried, al_event.begin());
  std::copy_n(rx_.begin() + static_cast<std::ptrdiff_t>(first), out.size(), out.begin());
  return carried;
}

void Et1100SpiPdi::write_once(std::uint16_t address, std::span<const std::uint8_t> in) noexcept {
  std::size_t n = address_phase(address, kCmdWrite);
  std::copy(in.begin(), in.end(), tx_.begin() + static_cast<std::ptrdiff_t>(n));
  n += in.size();
  if (transact(std::span(tx_).first(n), std::span(rx_).first(n))) {
    last_al_event_ = static_cast<std::uint16_t>(rx_[0] | (rx_[1] << 8));
  }
}

void Et1100SpiPdi::read(std::uint16_t address, std::span<std::uint8_t> out) noexcept {
  std::size_t done = 0;
  // A read that starts at the AL event request takes the bytes the address
  // phase returns and reads only the rest (none for a 2-byte read: a NOP).
  if (address == kAlEventRequest && !out.empty()) {
    const std::size_t phase = options_.three_byte_address ? 3 : 2;
    const std::size_t carried = std::min(phase, out.size());
    const auto rest = static_cast<std::uint16_t>(address + carried);
    std::uint8_t al[3]{};
    read_once(rest, out.subspan(carried, std::min(out.size() - carried, kMaxBurst)), al);
    std::copy_n(al, carried, out.begin());
    done = std::min(out.size(), carried + kMaxBurst);
  }
  while (done < out.size() && !failed()) {
    const std::size_t n = std::min(out.size() - done, kMaxBurst);
    read_once(static_cast<std::uint16_t>(address + done), out.subspan(done, n), {});
    done += n;
  }
  if (failed()) std::fill(out.begin(), out.end(), std::uint8_t{0});
}

void Et1100SpiPdi::write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept {
  for (std::size_t done = 0; done < in.size() && !failed();) {
    const std::size_t n = std::min(in.size() - done, kMaxBurst);
    write_once(static_cast<std::uint16_t>(address + done), in.subspan(done, n));
    done += n;
  }
}

}  // namespace ecat::pdi_spi
