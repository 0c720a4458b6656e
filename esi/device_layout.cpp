// Identity, ESC properties, mailbox, sync managers, FMMUs, DC and drive facts
// of a device file (docs/device-format.md "Elements").
#include <algorithm>
#include <array>
#include <charconv>
#include <limits>

#include <fmt/format.h>

#include "esi/device_attrs.hpp"
#include "esi/device_build.hpp"
#include "esi/device_failure.hpp"

namespace ecat::esi {
namespace {

constexpr std::uint64_t kU8 = 0xFF;
constexpr std::uint64_t kU16 = 0xFFFF;
constexpr std::uint64_t kU32 = 0xFFFFFFFF;
constexpr std::int64_t kI32Min = std::numeric_limits<std::int32_t>::min();
constexpr std::int64_t kI32Max = std::numeric_limits<std::int32_t>::max();
// The ESC address space is 64 KiB and process RAM starts at 0x1000
// (ESC datasheet section II, "Process data RAM").
constexpr std::uint64_t kMaxRamSize = 0x10000 - 0x1000;
constexpr std::uint64_t kMaxUnits = 16;
constexpr std::size_t kMaxPorts = 4;  // ports 0..3 (0x0007)  // FMMUs / SMs an ESC can have (0x0004/0x0005)

// CiA 402 6502h "supported drive modes" bits.
constexpr std::array<std::pair<std::string_view, unsigned>, 10> kDriveModeBits = {{
    {"PP", 0}, {"VL", 1}, {"PV", 2}, {"PT", 3}, {"HM", 5},
    {"IP", 6}, {"CSP", 7}, {"CSV", 8}, {"CST", 9}, {"CSTCA", 10},
}};

void build_identity(const ElementSpec& e, od::Identity& id) {
  id.vendor_id = static_cast<std::uint32_t>(attr_unsigned(e, "vendorId", kU32, 0));
  id.vendor_name = attr_text(e, "vendorName");
  id.product_code = static_cast<std::uint32_t>(attr_unsigned(e, "productCode", kU32, 0));
  id.revision = static_cast<std::uint32_t>(attr_unsigned(e, "revision", kU32, 0));
  id.serial = static_cast<std::uint32_t>(attr_unsigned(e, "serial", kU32, 0));
  id.name = attr_text(e, "name");
  id.type_name = attr_text(e, "type");
  id.group_type = attr_text(e, "groupType");
  id.group_name = attr_text(e, "groupName");
  id.device_type = static_cast<std::uint32_t>(attr_unsigned(e, "deviceType", kU32, 0));
  id.hardware_version = attr_text(e, "hardwareVersion");
  id.software_version = attr_text(e, "softwareVersion");
  id.placeholders = attr_list(e, "placeholders");
}

void build_esc(const ElementSpec& e, od::DeviceDescription& dev) {
  od::EscProperties& esc = dev.esc;
  esc.esc_type = static_cast<std::uint8_t>(attr_unsigned(e, "escType", kU8, esc.esc_type));
  esc.revision = static_cast<std::uint8_t>(attr_unsigned(e, "escRevision", kU8, esc.revision));
  esc.build = static_cast<std::uint16_t>(attr_unsigned(e, "build", kU16, esc.build));
  esc.fmmu_count = static_cast<std::uint8_t>(attr_unsigned(e, "fmmus", kMaxUnits, esc.fmmu_count));
  esc.sm_count = static_cast<std::uint8_t>(attr_unsigned(e, "syncManagers", kMaxUnits, esc.sm_count));
  esc.process_ram_bytes = static_cast<std::uint32_t>(attr_unsigned(e, "ramSize", kMaxRamSize, esc.process_ram_bytes));
  esc.eeprom_bytes = static_cast<std::uint16_t>(attr_unsigned(e, "eepromSize", kU16, esc.eeprom_bytes));
  esc.dc_supported = attr_bool(e, "dc", esc.dc_supported);
  esc.dc_64bit = attr_bool(e, "dc64", esc.dc_64bit);
  esc.no_lrw = attr_bool(e, "noLrw", esc.no_lrw);
  esc.no_read_write = attr_bool(e, "noReadWrite", esc.no_read_write);
  esc.pdi_control = static_cast<std::uint16_t>(attr_unsigned(e, "pdiControl", kU16, esc.pdi_control));
  esc.pdi_configuration = static_cast<std::uint16_t>(attr_unsigned(e, "pdiConfiguration", kU16, esc.pdi_configuration));
  esc.pdi_configuration2 = static_cast<std::uint16_t>(attr_unsigned(e, "pdiConfiguration2", kU16, esc.pdi_configuration2));
  esc.sync_impulse_length = static_cast<std::uint16_t>(attr_unsigned(e, "syncImpulseLength", kU16, esc.sync_impulse_length));
  esc.configured_station_alias = static_cast<std::uint16_t>(attr_unsigned(e, "alias", kU16, esc.configured_station_alias));
  // ESI PhysicsType: [Y,K,H, ]{0,4}; port 0 carries the master's frames, so it must exist.
  const std::string physics = attr_text(e, "physics", esc.physics);
  if (physics.empty() || physics.size() > kMaxPorts || physics.find_first_not_of("YKH ") != std::string::npos ||
      physics[0] == ' ') {
    fail_at(where_of(e, "physics"),
            fmt::format("Esc physics '{}': one letter per port 0..3 (Y or H MII, K E-bus, space unused), port 0 used",
                        physics));
  }
  esc.physics = physics;
  dev.bootstrap_supported = attr_bool(e, "bootstrap", dev.bootstrap_supported);
}

void build_mailbox(const ElementSpec& e, od::MailboxProtocols& mb) {
  mb.coe = attr_bool(e, "coe", mb.coe);
  mb.foe = attr_bool(e, "foe", mb.foe);
  mb.eoe = attr_bool(e, "eoe", mb.eoe);
  mb.soe = attr_bool(e, "soe", mb.soe);
  mb.sdo_info = attr_bool(e, "sdoInfo", mb.sdo_info);
  mb.pdo_assign = attr_bool(e, "pdoAssign", mb.pdo_assign);
  mb.pdo_config = attr_bool(e, "pdoConfig", mb.pdo_config);
  mb.complete_access = attr_bool(e, "completeAccess", mb.complete_access);
  mb.segmented_sdo = attr_bool(e, "segmentedSdo", mb.segmented_sdo);
  mb.pdo_upload = attr_bool(e, "pdoUpload", mb.pdo_upload);
}

void build_dc(const DeviceSpec& spec, od::DeviceDescription& dev) {
  const ElementSpec& e = spec.dc;
  od::SyncLimits& s = dev.sync;
  s.min_cycle_time_ns = static_cast<std::uint32_t>(attr_unsigned(e, "minCycleTime", kU32, s.min_cycle_time_ns));
  s.max_cycle_time_ns = static_cast<std::uint32_t>(attr_unsigned(e, "maxCycleTime", kU32, s.max_cycle_time_ns));
  s.free_run = attr_bool(e, "freeRun", s.free_run);
  s.sm_synchronous = attr_bool(e, "smSync", s.sm_synchronous);
  s.dc_sync0 = attr_bool(e, "dcSync0", s.dc_sync0);
  s.dc_sync1 = attr_bool(e, "dcSync1", s.dc_sync1);
  for (const auto& m : spec.op_modes) {
    od::DcOpMode mode;
    mode.name = attr_text(m, "name");
    mode.description = attr_text(m, "desc");
    mode.assign_activate = static_cast<std::uint16_t>(attr_unsigned(m, "assignActivate", kU16, 0));
    mode.cycle_time_sync0_factor = static_cast<std::int32_t>(attr_signed(m, "cycleTimeSync0Factor", kI32Min, kI32Max, 1));
    mode.shift_time_sync0 = static_cast<std::int32_t>(attr_signed(m, "shiftTimeSync0", kI32Min, kI32Max, 0));
    mode.cycle_time_sync1_factor = static_cast<std::int32_t>(attr_signed(m, "cycleTimeSync1Factor", kI32Min, kI32Max, 0));
    mode.shift_time_sync1 = static_cast<std::int32_t>(attr_signed(m, "shiftTimeSync1", kI32Min, kI32Max, 0));
    dev.dc_op_modes.push_back(std::move(mode));
  }
}

od::SmType sm_type(const ElementSpec& e) {
  const std::string t = attr_text(e, "type");
  if (t == "MailboxOut") return od::SmType::MailboxOut;
  if (t == "MailboxIn") return od::SmType::MailboxIn;
  if (t == "Outputs") return od::SmType::Outputs;
  if (t == "Inputs") return od::SmType::Inputs;
  if (t == "Unused") return od::SmType::Unused;
  fail_at(where_of(e, "type"), fmt::format("unknown SyncManager type '{}'", t));
}

void build_sync_managers(const DeviceSpec& spec, od::DeviceDescription& dev) {
  if (!spec.sync_managers) return;
  std::vector<bool> seen(dev.esc.sm_count, false);
  for (const auto& e : *spec.sync_managers) {
    const auto index = attr_unsigned(e, "index", kU8, 0);
    if (index >= dev.esc.sm_count) {
      fail_at(where_of(e, "index"), fmt::format("SyncManager {} does not exist: the ESC has {} (Esc syncManagers)",
                                                index, dev.esc.sm_count));
    }
    if (seen[index]) fail_at(where_of(e, "index"), fmt::format("duplicate SyncManager {}", index));
    seen[index] = true;
    if (dev.sync_managers.size() <= index) dev.sync_managers.resize(index + 1);
    od::SyncManagerConfig& sm = dev.sync_managers[index];
    sm.type = sm_type(e);
    sm.start_address = static_cast<std::uint16_t>(attr_unsigned(e, "start", kU16, 0));
    sm.default_size = static_cast<std::uint16_t>(attr_unsigned(e, "size", kU16, 0));
    sm.min_size = static_cast<std::uint16_t>(attr_unsigned(e, "minSize", kU16, 0));
    sm.max_size = static_cast<std::uint16_t>(attr_unsigned(e, "maxSize", kU16, 0));
    sm.control = static_cast<std::uint8_t>(attr_unsigned(e, "control", kU8, 0));
    sm.enable = attr_bool(e, "enable", true);
    const bool mailbox = sm.type == od::SmType::MailboxOut || sm.type == od::SmType::MailboxIn;
    if (mailbox && sm.default_size == 0) {
      fail_at(e.where, fmt::format("mailbox SyncManager {} needs a size", index));
    }
  }
}

void build_fmmus(const DeviceSpec& spec, od::DeviceDescription& dev) {
  if (!spec.fmmus) return;
  if (spec.fmmus->size() > dev.esc.fmmu_count) {
    fail_at(spec.fmmus_where, fmt::format("{} FMMUs listed but the ESC has {} (Esc fmmus)",
                                          spec.fmmus->size(), dev.esc.fmmu_count));
  }
  for (const auto& e : *spec.fmmus) {
    const std::string u = attr_text(e, "usage");
    if (u == "Outputs") dev.fmmus.push_back(od::FmmuUsage::Outputs);
    else if (u == "Inputs") dev.fmmus.push_back(od::FmmuUsage::Inputs);
    else if (u == "MailboxState") dev.fmmus.push_back(od::FmmuUsage::MailboxState);
    else if (u == "Unused") dev.fmmus.push_back(od::FmmuUsage::Unused);
    else fail_at(where_of(e, "usage"), fmt::format("unknown FMMU usage '{}'", u));
  }
}

void build_drive(const DeviceSpec& spec, od::DeviceDescription& dev) {
  if (spec.drive.where.file.empty()) return;
  od::DriveProfile drive;
  drive.supported_modes = drive_mode_bits(spec.drive);
  for (const auto& m : attr_list(spec.drive, "homingMethods")) {
    ElementSpec one;
    one.attrs.set("m", Attr{m, where_of(spec.drive, "homingMethods")});
    drive.homing_methods.push_back(static_cast<std::int8_t>(attr_signed(one, "m", -128, 127, 0)));
  }
  for (const auto& name : spec.plant_order) {
    const Attr& a = spec.plant.at(name);
    double v = 0;
    auto [end, ec] = std::from_chars(a.value.data(), a.value.data() + a.value.size(), v);
    if (ec != std::errc{} || end != a.value.data() + a.value.size()) {
      fail_at(a.where, fmt::format("Plant {} value '{}' is not a number", name, a.value));
    }
    drive.plant.emplace_back(name, v);
  }
  drive.axes = axis_layout(spec);
  dev.drive = std::move(drive);
}

}  // namespace

std::uint32_t drive_mode_bits(const ElementSpec& drive) {
  std::uint32_t bits = 0;
  for (const auto& m : attr_list(drive, "modes")) {
    auto it = std::find_if(kDriveModeBits.begin(), kDriveModeBits.end(),
                           [&](const auto& p) { return p.first == m; });
    if (it == kDriveModeBits.end()) fail_at(where_of(drive, "modes"), fmt::format("unknown drive mode '{}'", m));
    bits |= 1u << it->second;
  }
  return bits;
}

void build_layout(const DeviceSpec& spec, od::DeviceDescription& dev) {
  build_identity(spec.identity, dev.identity);
  build_esc(spec.esc, dev);
  build_mailbox(spec.mailbox, dev.mailbox);
  build_dc(spec, dev);
  build_sync_managers(spec, dev);
  build_fmmus(spec, dev);
  build_drive(spec, dev);
}

}  // namespace ecat::esi
