// A small stand-in for the ESC, seen from the PDI: a register file with the
// SM0/SM1 mailbox rules the CoE layer relies on (ESC datasheet Section I §8.2,
// shared/spec/esc-registers.md §7): SM0 full after the master's write until
// the PDI reads its last byte; SM1 full once the PDI writes its last byte,
// empty after the master reads it; repeat request/ack bits; AL event request
// bits 8/9. Plus master-side helpers the tests drive it with.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "common/le.hpp"
#include "esc/pdi.hpp"
#include "esc/registers.hpp"

namespace ecat::coe::test {

class FakeEsc : public esc::Pdi {
 public:
  static constexpr std::uint8_t kFull = 0x08;

  FakeEsc() : mem_(0x10000, 0) { set_state(0x02); }

  void configure_mailboxes(std::uint16_t sm0_start, std::uint16_t sm0_len, std::uint16_t sm1_start,
                           std::uint16_t sm1_len) {
    configure_sm(0, sm0_start, sm0_len, 0x26);
    configure_sm(1, sm1_start, sm1_len, 0x22);
  }
  void configure_sm(unsigned n, std::uint16_t start, std::uint16_t len, std::uint8_t control, bool enable = true) {
    const std::uint16_t r = esc::reg::sync_manager(n);
    store_le<std::uint16_t>(&mem_[r], start);
    store_le<std::uint16_t>(&mem_[r + 2], len);
    mem_[r + 4] = control;
    mem_[r + 5] = 0;
    mem_[r + 6] = enable ? 1 : 0;
  }
  void set_state(std::uint8_t state) { mem_[esc::reg::kAlStatus] = state; }

  // ---- PDI side -----------------------------------------------------------
  void read(std::uint16_t address, std::span<std::uint8_t> out) noexcept override {
    ++pdi_reads;
    for (std::size_t i = 0; i < out.size(); ++i) {
      const std::size_t a = address + i;
      out[i] = a < mem_.size() ? mem_[a] : 0;
    }
    const auto [s0, l0] = sm(0);
    if (full(0) && covers(address, out.size(), s0 + l0 - 1)) {
      mem_[status(0)] &= static_cast<std::uint8_t>(~kFull);
      clear_event(8);
    }
  }
  void write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept override {
    for (std::size_t i = 0; i < in.size(); ++i) {
      const std::size_t a = address + i;
      if (a >= mem_.size()) break;
      // SM status and activate bytes are not PDI-writable.
      if (a >= esc::reg::kSyncManagerBase && a < esc::reg::kSyncManagerBase + 0x80) {
        const std::size_t off = (a - esc::reg::kSyncManagerBase) % 8;
        if (off == 5 || off == 6) continue;
        if (off == 7 && (in[i] & 1)) {  // PDI deactivates the SM: buffer emptied
          mem_[a - 2] &= static_cast<std::uint8_t>(~kFull);
          ++deactivations;
        }
      }
      mem_[a] = in[i];
    }
    const auto [s1, l1] = sm(1);
    if (!full(1) && covers(address, in.size(), s1 + l1 - 1)) {
      mem_[status(1)] |= kFull;
      ++sm1_writes;
    }
  }

  // ---- master side ----------------------------------------------------------
  // Writes a whole mailbox into SM0 (padded); false if SM0 is still full.
  bool master_write(std::span<const std::uint8_t> frame) {
    if (full(0)) return false;
    const auto [s0, l0] = sm(0);
    for (std::size_t i = 0; i < l0; ++i) mem_[s0 + i] = i < frame.size() ? frame[i] : 0;
    mem_[status(0)] |= kFull;
    set_event(8);
    return true;
  }
  // Reads SM1; nothing (WKC 0) while it is empty.
  std::optional<std::vector<std::uint8_t>> master_read() {
    if (!full(1)) return std::nullopt;
    const auto [s1, l1] = sm(1);
    std::vector<std::uint8_t> out(mem_.begin() + s1, mem_.begin() + s1 + l1);
    mem_[status(1)] &= static_cast<std::uint8_t>(~kFull);
    return out;
  }
  void master_toggle_repeat() { mem_[esc::reg::sync_manager(1) + 6] ^= 0x02; }
  bool repeat_acked() const {
    return ((mem_[esc::reg::sync_manager(1) + 6] ^ mem_[esc::reg::sync_manager(1) + 7]) & 0x02) == 0;
  }
  bool full(unsigned n) const { return mem_[status(n)] & kFull; }
  std::vector<std::uint8_t>& memory() { return mem_; }

  int pdi_reads = 0;
  int sm1_writes = 0;
  int deactivations = 0;

 private:
  std::pair<std::size_t, std::size_t> sm(unsigned n) const {
    const std::uint16_t r = esc::reg::sync_manager(n);
    return {load_le<std::uint16_t>(&mem_[r]), load_le<std::uint16_t>(&mem_[r + 2])};
  }
  static std::uint16_t status(unsigned n) { return static_cast<std::uint16_t>(esc::reg::sync_manager(n) + 5); }
  static bool covers(std::size_t addr, std::size_t len, std::size_t byte) { return byte >= addr && byte < addr + len; }
  void set_event(unsigned bit) { mem_[esc::reg::kAlEventRequest + bit / 8] |= static_cast<std::uint8_t>(1u << (bit % 8)); }
  void clear_event(unsigned bit) {
    mem_[esc::reg::kAlEventRequest + bit / 8] &= static_cast<std::uint8_t>(~(1u << (bit % 8)));
  }

  std::vector<std::uint8_t> mem_;
};

}  // namespace ecat::coe::test
