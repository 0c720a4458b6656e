// A register file with just the AL event semantics the state machine relies
// on, standing in for an ESC in the ESM unit tests: an ECAT write of 0x0120
// sets AL event 0x0220 bit 0 (cleared by a PDI read of 0x0120), an ECAT
// write of an SM activation byte sets bit 4 (cleared by a PDI read of any
// SM activation byte), watchdog expiry sets bit 6 (cleared by reading 0x0440).
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <span>

#include "common/le.hpp"
#include "esc/pdi.hpp"
#include "esc/registers.hpp"

namespace ecat::esc::test {

class FakePdi final : public Pdi {
 public:
  static constexpr std::size_t kSize = 0x2000;
  static constexpr std::uint16_t kSync0Status = 0x098E;
  static constexpr std::uint16_t kDcBlock = 0x0900;
  static constexpr std::uint16_t kDcBlockSize = 0x0100;

  void read(std::uint16_t address, std::span<std::uint8_t> out) noexcept override {
    for (std::size_t i = 0; i < out.size(); ++i) {
      const std::size_t a = address + i;
      out[i] = a < kSize ? mem_[a] : 0;
      if (a == reg::kAlControl || a == reg::kAlControl + 1u) clear_event(1u << 0);
      if (a >= reg::kSyncManagerBase && a < reg::kSyncManagerBase + 16u * 8u &&
          (a - reg::kSyncManagerBase) % 8 == reg::sm::kActivate) {
        clear_event(1u << 4);
      }
      if (a == reg::kWatchdogStatusProcessData) clear_event(1u << 6);
      if (a >= kDcBlock && a < kDcBlock + kDcBlockSize && i == 0) ++dc_reads_[a - kDcBlock];
      if (a == kSync0Status) clear_event(1u << 2);  // DC SYNC0/SYNC1 acknowledge
      if (a == kSync0Status + 1u) clear_event(1u << 3);
    }
  }
  void write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept override {
    for (std::size_t i = 0; i < in.size(); ++i) {
      if (address + i < kSize) mem_[address + i] = in[i];
    }
  }

  // ECAT-side actions of a master.
  void master_al_control(std::uint16_t value) noexcept {
    store_le(&mem_[reg::kAlControl], value);
    set_event(1u << 0);
  }
  void master_sm(unsigned n, std::uint16_t start, std::uint16_t length, std::uint8_t control,
                 bool enable) noexcept {
    const std::size_t base = reg::sync_manager(n);
    store_le(&mem_[base + reg::sm::kStartAddress], start);
    store_le(&mem_[base + reg::sm::kLength], length);
    mem_[base + reg::sm::kControl] = control;
    mem_[base + reg::sm::kActivate] = enable ? 1 : 0;
    set_event(1u << 4);
  }
  void watchdog_expired(bool expired) noexcept {
    store_le<std::uint16_t>(&mem_[reg::kWatchdogStatusProcessData], expired ? 0 : 1);
    if (expired) set_event(1u << 6);
  }

  std::uint16_t u16(std::uint16_t address) const noexcept { return load_le<std::uint16_t>(&mem_[address]); }
  std::uint8_t u8(std::uint16_t address) const noexcept { return mem_[address]; }
  std::uint32_t events() const noexcept { return load_le<std::uint32_t>(&mem_[reg::kAlEventRequest]); }
  void poke_u16(std::uint16_t address, std::uint16_t v) noexcept { store_le(&mem_[address], v); }
  void poke_u8(std::uint16_t address, std::uint8_t v) noexcept { mem_[address] = v; }
  void poke_u32(std::uint16_t address, std::uint32_t v) noexcept { store_le(&mem_[address], v); }
  void poke_u64(std::uint16_t address, std::uint64_t v) noexcept { store_le(&mem_[address], v); }
  void raise_event(std::uint32_t bits) noexcept { set_event(bits); }
  // PDI reads that started at `address` of the DC block (0x0900-0x09FF).
  unsigned dc_reads(std::uint16_t address) const noexcept { return dc_reads_[address - kDcBlock]; }

 private:
  void set_event(std::uint32_t bit) noexcept {
    store_le(&mem_[reg::kAlEventRequest], static_cast<std::uint32_t>(events() | bit));
  }
  void clear_event(std::uint32_t bit) noexcept {
    store_le(&mem_[reg::kAlEventRequest], static_cast<std::uint32_t>(events() & ~bit));
  }
  std::array<std::uint8_t, kSize> mem_{};
  std::array<unsigned, kDcBlockSize> dc_reads_{};
};

}  // namespace ecat::esc::test
