// The PDI host protocol (pdi_client/ecat_pdi_protocol.h, docs/pdi-host.md)
// on bytes, without a socket: what one attached firmware's messages do to
// the ESC and what goes back. The socket side is pdi_host/pdi_host.hpp;
// tests drive this directly on simulated time.
//
// A malformed message (unknown type, reserved byte set, a payload of the
// wrong size, a range past 0xFFFF, an access the chosen PDI does not have)
// is refused with its reason: the caller closes the connection. Nothing a
// firmware sends can do more to the ESC than its PDI could on silicon.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "esc/esc.hpp"
#include "pdi_host/pdi_chip.hpp"
#include "pdi_spi/emulated_chip.hpp"

namespace ecat::pdi_host {

// What the firmware's interrupt input sees (the LINES payload).
struct PdiLines {
  std::uint32_t event_request = 0;  // 0x0220
  std::uint32_t event_mask = 0;     // 0x0204
  bool irq = false;                 // the IRQ line to the µC
  std::uint8_t sync = 0;            // ECAT_PDI_SYNC0/1 pulses since the last lines message

  bool same_level(const PdiLines& o) const noexcept {
    return event_request == o.event_request && event_mask == o.event_mask && irq == o.irq;
  }
};

class PdiSession {
 public:
  static constexpr std::size_t kHeaderSize = ECAT_PDI_HEADER_SIZE;
  static constexpr std::size_t kMaxMessage = ECAT_PDI_HEADER_SIZE + ECAT_PDI_MAX_PAYLOAD;
  static constexpr std::uint32_t kAddressSpace = 0x10000;  // a 16-bit PDI address

  // `chip`: the emulated SPI slave for PdiChip::Lan9252/Et1100Spi (it sits
  // on `esc`), null for PdiChip::Direct.
  PdiSession(esc::Esc& esc, PdiChip kind, pdi_spi::EmulatedChip* chip, const Clock& clock) noexcept
      : esc_(esc), kind_(kind), chip_(chip), clock_(clock) {}

  // The HELLO a new connection gets, then the lines as they are.
  void greet(std::vector<std::uint8_t>& out);
  // Handles up to `max_messages` whole messages at the front of `in`,
  // removes them and appends their replies to `out`; returns how many it
  // handled. An error is the reason the connection must close.
  Expected<std::size_t, std::string> handle(std::vector<std::uint8_t>& in, std::vector<std::uint8_t>& out,
                                            std::size_t max_messages);
  // Whether `in` starts with a whole message (handle has work).
  static bool has_message(const std::vector<std::uint8_t>& in) noexcept;
  // A NOTIFY when the lines changed since the last lines message or a SYNC
  // pulse came (`sync` bits); returns whether one was appended.
  bool notify(std::vector<std::uint8_t>& out, std::uint8_t sync);

  PdiLines lines() const noexcept;

 private:
  void append_lines(std::vector<std::uint8_t>& out, std::uint8_t type, std::uint8_t sync);
  Expected<void, std::string> one(std::uint8_t type, const std::uint8_t* payload, std::size_t length,
                                  std::vector<std::uint8_t>& out);

  esc::Esc& esc_;
  PdiChip kind_;
  pdi_spi::EmulatedChip* chip_;
  const Clock& clock_;
  PdiLines sent_{};
  bool sent_any_ = false;
};

// Appends a message header (type, 0, payload length) to `out`.
void put_header(std::vector<std::uint8_t>& out, std::uint8_t type, std::size_t payload_length);

}  // namespace ecat::pdi_host
