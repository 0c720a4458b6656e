// What the two SPI backends (LAN9252, ET1100) share: the esc::Pdi they
// implement, a transaction counter and a sticky error. Pdi calls cannot
// fail, so a bus error or a chip that never becomes ready is recorded here
// (and the read returns zeros); the host checks error() after each
// firmware pass and stops with the message.
#pragma once

#include <cstdint>
#include <span>

#include "esc/pdi.hpp"
#include "pdi_spi/spi_bus.hpp"

namespace ecat::pdi_spi {

class SpiPdi : public esc::Pdi {
 public:
  explicit SpiPdi(SpiBus& bus) noexcept : bus_(bus) {}

  const SpiCounters& counters() const noexcept { return counters_; }
  void reset_counters() noexcept { counters_ = {}; }
  bool failed() const noexcept { return error_ != nullptr; }
  // What went wrong first; "" when nothing did.
  const char* error() const noexcept { return error_ ? error_ : ""; }

 protected:
  // One counted transaction; false (and error() set) when the bus failed.
  bool transact(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept {
    ++counters_.transactions;
    counters_.bytes += tx.size();
    if (bus_.transfer(tx, rx)) return true;
    fail_with("SPI transfer failed");
    return false;
  }
  void fail_with(const char* what) noexcept {
    if (!error_) error_ = what;  // the first error is the one that matters
  }

 private:
  SpiBus& bus_;
  SpiCounters counters_;
  const char* error_ = nullptr;
};

}  // namespace ecat::pdi_spi
