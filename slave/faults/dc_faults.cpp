#include "slave/faults/dc_faults.hpp"

#include <fmt/format.h>

#include "esc/esc.hpp"

namespace ecat::slave::faults {

namespace {

std::int64_t param(const std::map<std::string, std::int64_t>& params, const char* name) {
  const auto it = params.find(name);
  return it == params.end() ? 0 : it->second;
}

}  // namespace

std::optional<DcFault> dc_fault(std::string_view kind) noexcept {
  if (kind == "dc_drift") return DcFault::Drift;
  if (kind == "dc_time_jump") return DcFault::TimeJump;
  if (kind == "sync0_stopped") return DcFault::Sync0Stopped;
  return std::nullopt;
}

Expected<DcFaultState, std::string> engage(DcFault fault, std::string_view kind, std::size_t slave, esc::Esc& esc,
                                           Nanoseconds now, const std::map<std::string, std::int64_t>& params) {
  if (!esc.config().dc) return fail(fmt::format("{}: slave {} has no distributed clock (0x0008 bit 2)", kind, slave));
  DcFaultState state;
  esc::DcUnit& dc = esc.dc();
  switch (fault) {
    case DcFault::Drift: {
      const std::int64_t ppm = param(params, "ppm");
      if (ppm == 0 || ppm < -kMaxDriftPpm || ppm > kMaxDriftPpm) {
        return fail(fmt::format("{}: ppm = {} is out of range (-{}..{}, not 0)", kind, ppm, kMaxDriftPpm, kMaxDriftPpm));
      }
      state.ppm_before = dc.clock().ppm();
      dc.set_oscillator_ppm(now, state.ppm_before + static_cast<double>(ppm));
      break;
    }
    case DcFault::TimeJump: {
      const std::int64_t ns = param(params, "ns");
      if (ns == 0) return fail(fmt::format("{}: ns = 0 changes nothing", kind));
      dc.jump_local_time(now, ns);
      break;
    }
    case DcFault::Sync0Stopped:
      if (dc.sync0_inhibited()) return fail(fmt::format("{}: SYNC0 of slave {} is already stopped", kind, slave));
      dc.inhibit_sync0(true);
      break;
  }
  return state;
}

void clear(DcFault fault, const DcFaultState& state, esc::Esc& esc, Nanoseconds now) noexcept {
  switch (fault) {
    case DcFault::Drift: esc.dc().set_oscillator_ppm(now, state.ppm_before); break;
    case DcFault::TimeJump: break;
    case DcFault::Sync0Stopped: esc.dc().inhibit_sync0(false); break;
  }
}

}  // namespace ecat::slave::faults
