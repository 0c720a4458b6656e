// The DC faults of slave::FaultCatalogue (docs/faults.md "DC"): a slave's
// oscillator drifting by a given ppm from now on, its local time jumping
// once, its SYNC unit no longer putting out SYNC0 though 0x0981 stays
// activated. Each acts on the ESC's DC unit (esc/dc/), where silicon would.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "common/clock.hpp"
#include "common/expected.hpp"

namespace ecat::esc {
class Esc;
}

namespace ecat::slave::faults {

enum class DcFault : std::uint8_t {
  Drift,         // dc_drift
  TimeJump,      // dc_time_jump
  Sync0Stopped,  // sync0_stopped
};

// What clear() needs to undo engage().
struct DcFaultState {
  double ppm_before = 0.0;  // Drift: the oscillator's own error before the fault
};

// dc_drift's ppm: beyond the time loop's +-1000 ppm correction
// (esc::TimeLoop::kMaxRateCorrection) on purpose, so a drift the ESC cannot
// follow can be engaged.
inline constexpr std::int64_t kMaxDriftPpm = 5000;

// The fault of a catalogue kind name; nullopt for a kind that is not one of these.
std::optional<DcFault> dc_fault(std::string_view kind) noexcept;

// Checks the parameters (messages name the kind and the slave) and acts at
// true time `now`; nothing changes when a check fails.
Expected<DcFaultState, std::string> engage(DcFault fault, std::string_view kind, std::size_t slave, esc::Esc& esc,
                                           Nanoseconds now, const std::map<std::string, std::int64_t>& params);
// Undoes it at `now`: the oscillator back to its own error (the time the
// drift gained stays: the time loop must win it back), SYNC0 again. A time
// jump is not undone: it happened.
void clear(DcFault fault, const DcFaultState& state, esc::Esc& esc, Nanoseconds now) noexcept;

}  // namespace ecat::slave::faults
