// Distributed-clocks unit of one ESC: registers 0x0900-0x09FF (ESC datasheet
// Section I §9, Section II §10; shared/spec/esc-registers.md §10). The Esc
// routes every access in that block here with the time of the access.
// This first version only stores the registers; the DC engineer fills in
// receive-time latching, system time, the time loop and SYNC/LATCH.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "common/clock.hpp"
#include "esc/access_side.hpp"

namespace ecat::esc {

class DcUnit {
 public:
  static constexpr std::uint16_t kSize = 0x0100;  // 0x0900..0x09FF

  // `offset` is relative to 0x0900; offset + size <= kSize (the Esc clips).
  void read(std::uint16_t offset, std::span<std::uint8_t> out, Nanoseconds local_time,
            Side side = Side::Ecat) noexcept;
  void write(std::uint16_t offset, std::span<const std::uint8_t> in, Nanoseconds local_time,
             Side side = Side::Ecat) noexcept;
  // A frame reached `port` at time t (before the ESC processes it for port 0,
  // on its way back for the other ports).
  void on_frame_arrival(int port, Nanoseconds t) noexcept;
  // Advances SYNC/LATCH generation to `now`; returns when it next needs to run.
  std::optional<Nanoseconds> poll(Nanoseconds now) noexcept;

  // Event bits the unit currently requests: AL event request 0x0220 bits
  // 1..3 (latch, SYNC0, SYNC1) and ECAT event request 0x0210 bit 0 (latch).
  // The Esc ORs them into its event registers.
  std::uint32_t al_event_request() const noexcept { return al_events_; }
  std::uint16_t ecat_event_request() const noexcept { return ecat_events_; }

  // Power-on/ESC reset; `sync_pulse_length` is SII word 2 (-> 0x0982).
  void reset(std::uint16_t sync_pulse_length) noexcept;

 private:
  std::array<std::uint8_t, kSize> regs_{};
  std::uint32_t al_events_ = 0;
  std::uint16_t ecat_events_ = 0;
};

}  // namespace ecat::esc
