// Datasheet figures for the time a frame spends inside an ESC, per ESC type
// (register 0x0000, Section II §2.1.1) and per port type (0x0007: E-bus or
// MII; an MII port adds its PHY's RX and TX delays, Section I §5), and the
// defaults an ESC of that type gets from them (docs/esc.md "Forwarding delay
// figures per ESC type"). A figure that no public source gave stays empty
// and counts as 0: the cable delays carry that time (Segment::kDefaultHopDelay).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "common/clock.hpp"
#include "esc/esc_config.hpp"

namespace ecat::esc {

// ESC type codes (0x0000) of the ESCs the figures table names (Section II
// §2.1.1 for the Beckhoff ones; the vendor codes as masters decode them).
inline constexpr std::uint8_t kEscTypeEsc20 = 0x02;     // ESC10, ESC20 (FPGA)
inline constexpr std::uint8_t kEscTypeIpCore = 0x04;    // customer FPGA IP core
inline constexpr std::uint8_t kEscTypeEt1200 = 0x12;    // ET120x
inline constexpr std::uint8_t kEscTypeTi = 0x90;        // TI (PRU-ICSS, C2000 ESC)
inline constexpr std::uint8_t kEscTypeInfineon = 0x98;  // XMC4x00
inline constexpr std::uint8_t kEscTypeRenesas = 0xA0;
inline constexpr std::uint8_t kEscTypeMicrochip = 0xC0; // LAN9252/LAN9253
// kEscTypeEt1100 (0x11, also ET1150) is in esc_config.hpp.

// One ESC type's figures. The time is the one docs/esc.md "Forwarding delays
// inside an ESC" gives EscConfig: from the frame's start at the receiving
// port to its start at the next open port, through the processing unit
// (entering at port 0, Section I §3.2 "processing" direction) or alongside it
// (entering at port 1..3, "forwarding" direction). The port type is that of
// the port the frame enters.
struct InnerDelayFigures {
  std::uint8_t esc_type = 0;
  std::string_view name;
  std::optional<Nanoseconds> processing_ebus;
  std::optional<Nanoseconds> processing_mii;
  std::optional<Nanoseconds> forwarding_ebus;
  std::optional<Nanoseconds> forwarding_mii;
  // Where the figures come from (document, section/table), or what was
  // searched and not found.
  std::string_view source;
};

// The figures this project could source (docs/esc.md lists every ESC type
// and its source; "not found" ones have no figure).
std::span<const InnerDelayFigures> datasheet_inner_delays() noexcept;

// The entry for an ESC type in a table, or null.
const InnerDelayFigures* find_inner_delays(std::span<const InnerDelayFigures> table, std::uint8_t esc_type) noexcept;

// The type of each port as 0x0007 reports it (two bits per port, port 0 =
// bits 1:0).
std::array<PortType, kMaxPorts> port_types(std::uint8_t port_descriptor) noexcept;

// EscConfig's delays for an ESC of a type with ports of these types:
// processing from port 0's type, forwarding per port 1..3 from that port's
// type; a figure the table lacks gives 0.
struct InnerDelays {
  Nanoseconds processing{0};
  std::array<Nanoseconds, kMaxPorts> forwarding{};  // [0] unused: port 0 enters the unit
};
InnerDelays inner_delays_for(const InnerDelayFigures* figures, const std::array<PortType, kMaxPorts>& ports) noexcept;

}  // namespace ecat::esc
