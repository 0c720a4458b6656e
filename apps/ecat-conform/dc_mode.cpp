// Which synchronisation the suite runs a device in (suite.hpp, DcSync0): a
// device whose ESI lists Dc/OpMode elements, none of them without DC
// (AssignActivate 0, "FreeRun"/"SM-Synchron"), can only be configured in
// DC by a master that follows its ESI (TwinCAT offers the listed OpModes
// only). The suite then takes the first OpMode: SYNC0 from its
// CycleTimeSync0 Factor and the master cycle, and its ShiftTimeSync0.
#include <algorithm>

#include <fmt/format.h>

#include "apps/ecat-conform/target.hpp"

namespace ecat::conform {

std::optional<master::conformance::DcSync0> dc_only_mode(const od::DeviceDescription& device,
                                                         std::uint32_t master_cycle_ns) {
  constexpr std::uint16_t kSyncUnitAndSync0 = 0x0300;  // 0x0980/0x0981: SYNC unit active, SYNC0 (ETG.1000.4)
  const auto& modes = device.dc_op_modes;
  if (modes.empty()) return std::nullopt;
  if (std::any_of(modes.begin(), modes.end(), [](const od::DcOpMode& m) { return m.assign_activate == 0; })) {
    return std::nullopt;
  }
  const od::DcOpMode& m = modes.front();
  if ((m.assign_activate & kSyncUnitAndSync0) != kSyncUnitAndSync0) return std::nullopt;
  master::conformance::DcSync0 dc;
  // CycleTimeSync0@Factor (ETG.2000 Dc/OpMode): the master cycle times a
  // positive factor, divided by a negative one's magnitude.
  const std::int64_t f = m.cycle_time_sync0_factor;
  dc.cycle_ns = f > 0 ? master_cycle_ns * static_cast<std::uint32_t>(f)
                : f < 0 ? static_cast<std::uint32_t>(master_cycle_ns / static_cast<std::uint64_t>(-f))
                        : master_cycle_ns;
  dc.shift_ns = m.shift_time_sync0 > 0 ? static_cast<std::uint32_t>(m.shift_time_sync0) : 0;
  dc.why = fmt::format("the ESI offers only DC OpModes; OpMode '{}' (AssignActivate #x{:04X}): SYNC0 {} ns, shift {} ns",
                       m.name, m.assign_activate, dc.cycle_ns, dc.shift_ns);
  return dc;
}

}  // namespace ecat::conform
