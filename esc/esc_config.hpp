// Construction-time description of one emulated ESC (Beckhoff ESC datasheet
// Section II §2: ESC information 0x0000-0x0008). The ESC knows nothing of
// CoE: the slave layer fills this from the device model (SII image, ports).
// Defaults describe an ET1100 with 2 MII ports, 8 FMMUs, 8 SMs, 8 KiB RAM.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "common/clock.hpp"
#include "esc/eeprom_image.hpp"

namespace ecat::esc {

// ESC type codes (0x0000), Section II Table 2.
inline constexpr std::uint8_t kEscTypeEt1100 = 0x11;
inline constexpr std::uint8_t kMaxPorts = 4;
inline constexpr std::uint8_t kMaxFmmus = 16;
inline constexpr std::uint8_t kMaxSyncManagers = 16;
inline constexpr std::uint32_t kMaxProcessRam = 0x10000 - 0x1000;  // 60 KiB

// Port descriptor 0x0007, two bits per port.
enum class PortType : std::uint8_t { NotImplemented = 0b00, NotConfigured = 0b01, Ebus = 0b10, Mii = 0b11 };
inline constexpr unsigned kPortTypeMask = 0b11;
inline constexpr std::uint8_t port_descriptor_bits(unsigned port, PortType t) {
  return static_cast<std::uint8_t>(static_cast<unsigned>(t) << (2 * port));
}
// The type of `port` in a port descriptor (the inverse of port_descriptor_bits).
inline constexpr PortType port_type_in(std::uint8_t port_descriptor, unsigned port) {
  return static_cast<PortType>((port_descriptor >> (2 * port)) & kPortTypeMask);
}

// Called when the master writes an SII word through 0x0502 (write command),
// so the owner can persist it. Set-up only; never called on the cyclic path
// except for an SII write command.
using SiiWriteBack = std::function<void(std::uint16_t word_address, std::uint16_t value)>;

struct EscConfig {
  // Fast paths (issue 8): register bytes without side effects copied as a
  // block, byte-aligned FMMUs routed straight to their SM. false sends every
  // access through the per-byte checked handlers instead - same behaviour,
  // slower; the tests run both and compare (tests/esc/esc_fast_path_test.cpp).
  // First: every datagram asks for it, as it does for dc and lrw below, so
  // that the three sit in the Esc object's first line or two (issue 30
  // item 1).
  bool fast_paths = true;
  std::uint8_t type = kEscTypeEt1100;
  std::uint8_t revision = 0x00;
  std::uint16_t build = 0x0000;
  std::uint8_t fmmu_count = 8;           // <= kMaxFmmus
  std::uint8_t sync_manager_count = 8;   // <= kMaxSyncManagers
  std::uint32_t process_ram_size = 8 * 1024;  // bytes at 0x1000.., <= kMaxProcessRam, multiple of 1 KiB
  // Where the memory block starts in its mapping: memory_colour x
  // kMemoryColourStep bytes (taken modulo kMemoryColours; esc/esc_memory.cpp).
  // Neighbours in a line with different colours do not have the same register
  // at the same address modulo 4 KiB, which the CPU takes for one address
  // until it has compared them in full (a frame stores to a register of one
  // ESC, then loads it at the next). slave::Chain gives each slave its
  // position: memory_colour_at(i).
  static constexpr std::size_t kMemoryColourStep = 64;  // one cache line
  static constexpr std::size_t kMemoryColours = 8;
  static constexpr std::uint8_t memory_colour_at(std::size_t position) noexcept {
    return static_cast<std::uint8_t>(position % kMemoryColours);
  }
  std::uint8_t memory_colour = 0;
  std::uint8_t port_count = 2;           // ports 0..port_count-1 exist, <= kMaxPorts
  PortType port_type = PortType::Mii;    // type reported for each existing port in 0x0007
  // Port descriptor 0x0007 given per port (two bits each, port 0 = bits 1:0):
  // when not 0 it replaces port_count/port_type, and a port exists when its
  // bits are not 00 ("not implemented") - e.g. 0x3B for a coupler with port 0
  // MII, port 1 E-bus, port 2 MII and no port 3 (Section II 0x0007).
  std::uint8_t port_descriptor = 0;

  // Features 0x0008.
  bool dc = true;               // bit 2: DC available (0x0900-0x09FF routed to DcUnit)
  bool dc_64bit = true;         // bit 3
  bool enhanced_dc_sync = true; // bit 8
  bool lrw = true;              // bit 9 set when false: LRW passes with WKC untouched
  bool read_write_commands = true;  // bit 10 set when false: APRW/FPRW/BRW pass untouched

  // SII EEPROM image (bytes, little-endian words). Words 0..4 initialise
  // 0x0140/0x0141, 0x0150/0x0151, 0x0982 (via DcUnit), 0x0152 and the alias
  // 0x0012 at power-on, as an ET1100 does after its EEPROM load. Shared
  // copy-on-write between ESCs given the same image (esc/eeprom_image.hpp).
  EepromImage sii;
  SiiWriteBack sii_write_back;
  // Time the SII interface stays busy after a command (0: finishes at once,
  // which every common master accepts - shared/spec/masters.md §6 #8).
  Nanoseconds sii_busy_time{0};
  // Read size reported in 0x0502 bit 6: true = 8 bytes (as an ET1100), false = 4 bytes.
  bool sii_read_8_bytes = true;
  // Time a frame spends inside this ESC, from its start at a receiving port
  // to its start at the next open port (docs/esc.md "Forwarding delays
  // inside an ESC"): through the processing unit (port 0 -> EtherCAT
  // processing unit -> out, the "processing" direction) and port to port
  // without it (the "forwarding" direction, Section I §3.2). A frame that
  // enters at port 1..3 and reaches the unit through a closed port 0 takes
  // both. 0 (the default): the cables carry all the time (esc::Segment).
  Nanoseconds processing_delay{0};
  Nanoseconds forwarding_delay{0};
  // Forwarding delay per receiving port 1..3 where set ([0] unused), in
  // place of forwarding_delay: E-bus and MII ports differ (an MII port adds
  // its PHY's delays, Section I §5). The slave layer sets them from the ESC
  // type's figures (esc/inner_delay_figures.hpp, docs/esc.md "Forwarding
  // delay figures per ESC type").
  std::array<std::optional<Nanoseconds>, kMaxPorts> port_forwarding_delay{};

  // A PDI read of SM n's status register 0x0805+8n also clears AL event bit
  // 8+n. Silicon does not do this: the bit mirrors the status interrupt bits,
  // which only an access to the buffer clears (Section II 0x0220, 0x0805), and
  // SOES depends on it (docs/pdi-host.md). The built-in firmware (slave::
  // Firmware) still relies on the clearing to let its IRQ drop - without it
  // it is woken on every frame (tests/slave/firmware_events_test.cpp,
  // spi_cycle_cost_test.cpp) - so it stays the default until that firmware
  // clears its events as on silicon; a slave whose firmware is another
  // process (SlaveOptions::external_firmware) gets silicon's rule.
  bool sm_status_read_clears_event = true;
};

}  // namespace ecat::esc
