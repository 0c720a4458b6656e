#include "ds402/drive_config.hpp"

#include <array>

#include "common/le.hpp"

namespace ecat::ds402 {

namespace {
using namespace supported;
using namespace error_register;

void allow(DriveConfig& c, int from, int to) {
  for (int m = from; m <= to; ++m) c.allow_homing(static_cast<std::int8_t>(m));
}

OptionCode values(std::initializer_list<std::int16_t> list, std::int16_t def) {
  OptionCode o{0, def};
  for (std::int16_t v : list) o.allowed = static_cast<std::uint16_t>(o.allowed | (1u << v));
  return o;
}

// SIMTACH RSE V3 (seed 002): 6502h = 0x3AD; homing 17-30 and 35 only (no
// index-pulse methods); option codes 0-6 with defaults 2/0/1/-/1; no 603Fh
// values in the manual, so the CiA 402 codes ("consistent with DS402").
DriveConfig simtach() {
  DriveConfig c;
  c.name = "simtach-rse";
  c.supported_modes = kPp | kPv | kTq | kHm | kCsp | kCsv | kCst;
  c.homing_methods.reset();
  allow(c, 17, 30);
  c.allow_homing(35);
  c.quick_stop = OptionCode::range(0, 6, 2);
  c.shutdown = OptionCode::range(0, 1, 0);
  c.disable_operation = OptionCode::range(0, 1, 1);
  c.halt = OptionCode::range(1, 2, 1);
  c.fault_reaction = OptionCode::range(0, 2, 1);
  c.home_found_bit = 1u << 15;  // SW15 "home found"
  return c;
}

// Yaskawa Σ-V-SD (seed 003): 6502h = 0x3ED (IP is advertised but not
// simulated here); homing 1, 2, 7-14, 24, 28, 33-35; 605Ah 0-3 (default 2),
// 605Bh 0-1 (0), 605Ch 0-1 (1), 605Dh 1-3 (1), 605Eh 0 only. EMCY code is
// always FF00h with the alarm number in bytes 4-5; 603Fh carries the
// SERVOPACK alarm: A.d00, A.510, A.710, A.12 (the numbers of the Σ-V alarm
// list the manual refers to).
DriveConfig yaskawa() {
  DriveConfig c;
  c.name = "yaskawa-sigma5-sd";
  c.supported_modes = kPp | kPv | kTq | kHm | kIp | kCsp | kCsv | kCst;
  c.homing_methods.reset();
  allow(c, 1, 2);
  allow(c, 7, 14);
  c.allow_homing(24);
  c.allow_homing(28);
  allow(c, 33, 35);
  c.quick_stop = OptionCode::range(0, 3, 2);
  c.shutdown = OptionCode::range(0, 1, 0);
  c.disable_operation = OptionCode::range(0, 1, 1);
  c.halt = OptionCode::range(1, 3, 1);
  c.fault_reaction = OptionCode::range(0, 0, 0);
  c.fault_codes = {{{0x0D00, kManufacturer},
                    {0x0D00, kManufacturer},
                    {0x0D00, kManufacturer},
                    {0x0D00, kManufacturer},
                    {0x0510, kManufacturer},
                    {0x0710, kManufacturer},
                    {0x0012, kCommunication}}};
  c.emcy_code = 0xFF00;
  return c;
}

// Welcon (seed 000): 6502h = 0x3AF (vl advertised and simulated, ds402/velocity_mode.hpp); homing
// -4, -3, 1-14, 17-30, 33-35, 37; 605Ah {0,1,2,5,6} default 6; 605Dh 0-2 default 1;
// 605Eh 0 only. Codes from its error table: 8611h following error, FF03h/FF04h
// limit switches, 7310h speed error, FF02h overload, 7500h communication.
DriveConfig welcon() {
  DriveConfig c;
  c.name = "welcon";
  c.homing_current_threshold_index = 0x2402;
  c.supported_modes = kPp | kVl | kPv | kTq | kHm | kCsp | kCsv | kCst;
  c.homing_methods.reset();
  allow(c, 1, 14);
  allow(c, 17, 30);
  allow(c, 33, 35);
  c.allow_homing(37);
  allow(c, -4, -3);  // current threshold on a mechanical stop (§5.4.3.33/34)
  c.quick_stop = values({0, 1, 2, 5, 6}, 6);
  c.shutdown = OptionCode::range(0, 1, 0);
  c.disable_operation = OptionCode::range(0, 1, 1);
  c.halt = OptionCode::range(1, 2, 1);
  c.fault_reaction = OptionCode::range(0, 0, 0);
  c.fault_codes = {{{0x8611, kDeviceProfile},
                    {0x8612, kDeviceProfile},
                    {0xFF03, kManufacturer},
                    {0xFF04, kManufacturer},
                    {0x7310, kManufacturer},
                    {0xFF02, kManufacturer},
                    {0x7500, kCommunication}}};
  return c;
}

// Leadshine iSV2-CAN (seed 004): PP, PV, PT, HM (6502h printed 0); homing
// 1-14, 17-30, 33-35, 37; 605Ah 0-3, 5-7 (no 4) default 2; 605Bh/605Ch 0-1
// default 0; 605Dh 1-3 default 1; no 605Eh (fixed to "disable drive").
// Codes from its alarm table: Er180 8611h, Er260 7329h (limit switches),
// Er1A0 8402h, Er100 8311h, Er81A 871Ah.
DriveConfig leadshine() {
  DriveConfig c;
  c.name = "leadshine-isv2-can";
  c.supported_modes = kPp | kPv | kTq | kHm;
  c.homing_methods.reset();
  allow(c, 1, 14);
  allow(c, 17, 30);
  allow(c, 33, 35);
  c.allow_homing(37);
  c.quick_stop = values({0, 1, 2, 3, 5, 6, 7}, 2);
  c.shutdown = OptionCode::range(0, 1, 0);
  c.disable_operation = OptionCode::range(0, 1, 0);
  c.halt = OptionCode::range(1, 3, 1);
  c.fault_reaction = OptionCode::range(0, 0, 0);
  c.fault_codes = {{{0x8611, kDeviceProfile},
                    {0x8612, kDeviceProfile},
                    {0x7329, kManufacturer},
                    {0x7329, kManufacturer},
                    {0x8402, kDeviceProfile},
                    {0x8311, kCurrent},
                    {0x871A, kCommunication}}};
  c.home_found_bit = 1u << 15;  // "origin found"
  return c;
}

constexpr std::array<std::string_view, 4> kNames{"simtach-rse", "yaskawa-sigma5-sd", "welcon",
                                                 "leadshine-isv2-can"};

std::int16_t as_i16(const od::Value& v) {
  if (v.size() < 2) return v.empty() ? 0 : static_cast<std::int16_t>(static_cast<std::int8_t>(v[0]));
  return static_cast<std::int16_t>(load_le<std::uint16_t>(v.data()));
}

void apply_option(OptionCode& o, const od::Dictionary& d, std::uint16_t index) {
  const od::Entry* e = d.find(index, 0);
  if (!e) return;
  if (e->has_min() && e->has_max()) {
    const std::int16_t lo = std::max<std::int16_t>(0, as_i16(e->min_value));
    const std::int16_t hi = std::min<std::int16_t>(15, as_i16(e->max_value));
    if (lo <= hi) o.allowed = OptionCode::range(lo, hi, 0).allowed;
  }
  if (!e->default_value.empty()) o.default_value = as_i16(e->default_value);
}
}  // namespace

DriveConfig generic_drive() {
  DriveConfig c;
  allow(c, 1, 14);
  allow(c, 17, 30);
  allow(c, 33, 35);
  c.allow_homing(37);
  return c;
}

std::optional<DriveConfig> drive_personality(std::string_view name) {
  if (name == "generic") return generic_drive();
  if (name == kNames[0]) return simtach();
  if (name == kNames[1]) return yaskawa();
  if (name == kNames[2]) return welcon();
  if (name == kNames[3]) return leadshine();
  return std::nullopt;
}

std::span<const std::string_view> personality_names() noexcept { return kNames; }

DriveConfig apply_device(DriveConfig c, const od::DeviceDescription& device) {
  if (device.drive) {
    if (device.drive->supported_modes != 0) c.supported_modes = device.drive->supported_modes;
    if (!device.drive->homing_methods.empty()) {
      c.homing_methods.reset();
      for (std::int8_t m : device.drive->homing_methods) c.allow_homing(m);
    }
  }
  const od::Dictionary& d = device.dictionary;
  apply_option(c.quick_stop, d, 0x605A);
  apply_option(c.shutdown, d, 0x605B);
  apply_option(c.disable_operation, d, 0x605C);
  apply_option(c.halt, d, 0x605D);
  apply_option(c.fault_reaction, d, 0x605E);
  return c;
}

}  // namespace ecat::ds402
