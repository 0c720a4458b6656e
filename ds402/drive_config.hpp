// Per-drive personality: which modes (6502h) and homing methods (60E3h) a
// drive offers, which option-code values it accepts, and its error codes.
// The seed drives' personalities follow their manuals (docs/ds402.md); a
// device file's DriveProfile and dictionary can override them.
#pragma once

#include <bitset>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "ds402/faults.hpp"
#include "ds402/modes.hpp"
#include "od/device.hpp"

namespace ecat::ds402 {

// The values 0..15 an option code accepts, and the one used when the object
// holds a value outside them (e.g. a vendor's reserved code).
struct OptionCode {
  std::uint16_t allowed = 0;  // bit n: value n accepted
  std::int16_t default_value = 0;

  static constexpr OptionCode range(std::int16_t lo, std::int16_t hi, std::int16_t def) noexcept {
    OptionCode o{0, def};
    for (std::int16_t v = lo; v <= hi; ++v) o.allowed = static_cast<std::uint16_t>(o.allowed | (1u << v));
    return o;
  }
  constexpr bool allows(std::int16_t v) const noexcept { return v >= 0 && v < 16 && (allowed >> v) & 1u; }
  constexpr std::int16_t pick(std::int16_t v) const noexcept { return allows(v) ? v : default_value; }
};

struct DriveConfig {
  std::string name = "generic";
  std::bitset<256> homing_methods;  // bit (method + 128)
  FaultCodes fault_codes = cia402_fault_codes();
  // Some drives send every EMCY with one manufacturer code and put their
  // alarm number (603Fh) into the manufacturer bytes 4-5 (Yaskawa: FF00h).
  std::optional<std::uint16_t> emcy_code;
  // Manufacturer statusword bit (14/15) that reads 1 once homing succeeded
  // ("home found"/"origin found" of SIMTACH and Leadshine); 0 = none.
  std::uint16_t home_found_bit = 0;
  // Manufacturer object holding the current threshold of homing methods
  // -3/-4 (Welcon: 2402h, UNSIGNED32 mA); 0 = none.
  std::uint16_t homing_current_threshold_index = 0;
  // What every cycle reads, last and together: next to the drive's Plant,
  // whose state the cycle reads too (one cache line; issue 30 item 1).
  std::uint32_t supported_modes = kSimulatedModes;  // 6502h
  OptionCode quick_stop = OptionCode::range(0, 8, 2);         // 605Ah
  OptionCode shutdown = OptionCode::range(0, 1, 0);           // 605Bh
  OptionCode disable_operation = OptionCode::range(0, 1, 1);  // 605Ch
  OptionCode halt = OptionCode::range(1, 4, 1);               // 605Dh
  OptionCode fault_reaction = OptionCode::range(0, 4, 2);     // 605Eh

  bool supports_mode(std::int8_t mode) const noexcept {
    const std::uint32_t bit = supported_bit(mode);
    return bit != 0 && (supported_modes & bit) != 0;
  }
  bool supports_homing(std::int8_t method) const noexcept { return homing_methods.test(method + 128); }
  void allow_homing(std::int8_t method) noexcept { homing_methods.set(method + 128); }
};

// Every mode this simulator implements, homing methods 1-14, 17-30, 33-35, 37.
DriveConfig generic_drive();

// "simtach-rse", "yaskawa-sigma5-sd", "welcon", "leadshine-isv2-can".
std::optional<DriveConfig> drive_personality(std::string_view name);
std::span<const std::string_view> personality_names() noexcept;

// Applies a device description: 6502h and the homing methods from its
// DriveProfile, the option-code ranges and defaults from the dictionary's
// 605Ah-605Eh entries (min/max/default), when given.
DriveConfig apply_device(DriveConfig base, const od::DeviceDescription& device);

}  // namespace ecat::ds402
