// Watchdog timing (Section II 0x0400-0x0443): base unit = (divider + 2) x 40 ns.
#include "esc/watchdog.hpp"

#include <algorithm>

namespace ecat::esc {

void Watchdogs::reset() noexcept {
  pd_deadline_ = kNever;
  pdi_deadline_ = kNever;
  set_times(kWatchdogDividerReset, kWatchdogTimeReset, kWatchdogTimeReset);
  // As the ESC's reset leaves its registers: 0x0440 bit 0 set, DL status
  // bit 1 clear until the first PDI access.
  set_status_shown(true, false);
}

Watchdogs::Expired Watchdogs::check(Nanoseconds now) noexcept {
  Expired e;
  if (pd_deadline_ != kNever && now >= pd_deadline_) {
    e.process_data = true;
    pd_status_shown_ = false;  // the caller clears 0x0440 bit 0
    pd_deadline_ = kNever;  // expires once; the next trigger re-arms it
  }
  if (pdi_deadline_ != kNever && now >= pdi_deadline_) {
    e.pdi = true;
    pdi_status_shown_ = false;  // the caller clears DL status bit 1
    pdi_deadline_ = kNever;
  }
  return e;
}

}  // namespace ecat::esc
