// DC unit: SYNC0/SYNC1 outputs and LATCH inputs over time (ESC datasheet
// Section I §9.2.4/§9.2.5, Section II 0x0980-0x09CF).
#include <algorithm>

#include "common/le.hpp"
#include "esc/dc/dc_registers.hpp"
#include "esc/dc/dc_unit.hpp"

namespace ecat::esc {
namespace {

using namespace dcreg;

constexpr std::uint16_t kU32 = 4;
constexpr unsigned kHighWordShift = 32;
constexpr std::uint64_t kLowWordMask = 0xFFFFFFFFull;

}  // namespace

// 0x0981 write by the owner: bit 0 arms or stops the unit (only a 0->1 edge
// re-arms, so a master deactivates before re-programming); bit 7 gives one
// debug pulse and clears itself.
void DcUnit::activation_written(Nanoseconds t) noexcept {
  wake_ = Nanoseconds::min();  // a pulse may now be scheduled (wake_bound)
  std::uint8_t& activation = regs_[kActivation];
  const std::uint64_t now = system_time(t);
  if ((activation & kDebugPulse) != 0) {
    activation = static_cast<std::uint8_t>(activation & ~kDebugPulse);
    if ((activation & kActivateSync0) != 0) pulse({0, now});
    if ((activation & kActivateSync1) != 0) pulse({1, now});
  }
  const bool on = (activation & kActivateSyncUnit) != 0;
  if (on && !sync_.active()) {
    sync_.activate({activation, load_le<std::uint64_t>(&regs_[kStartTimeCyclicOperation]),
                    load_le<std::uint32_t>(&regs_[kSync0CycleTime]), load_le<std::uint32_t>(&regs_[kSync1CycleTime])},
                   now);
  } else if (!on && sync_.active()) {
    sync_.deactivate();
  }
}

// 0x0990 write: with 0x0981 bit 4 a 32-bit write is extended to the next
// matching 64-bit time; with bit 3 the write activates the unit.
void DcUnit::start_time_written(std::uint16_t first, std::uint16_t end, Nanoseconds t) noexcept {
  std::uint8_t& activation = regs_[kActivation];
  const std::uint64_t now = system_time(t);
  const bool high_written = touches_high(first, end);
  if ((activation & kStartTimeExtension) != 0 && !high_written) {
    const std::uint64_t low = load_le<std::uint32_t>(&regs_[kStartTimeCyclicOperation]);
    std::uint64_t start = (now & ~kLowWordMask) | low;
    if (start <= now) start += 1ull << kHighWordShift;
    store_le(&regs_[kStartTimeCyclicOperation], start);
  }
  if ((activation & kAutoActivation) != 0) {
    activation = static_cast<std::uint8_t>(activation | kActivateSyncUnit);
    sync_.deactivate();
    activation_written(t);
  }
}

bool DcUnit::touches_high(std::uint16_t first, std::uint16_t end) noexcept {
  const auto high = static_cast<std::uint16_t>(kStartTimeCyclicOperation + kU32);
  return first < high + kU32 && high < end;
}

// A pulse from the generator (or the debug bit): output high, AL event
// 0x0220 bit 2/3; in pulse mode it ends after 0x0982 x 10 ns, in acknowledge
// mode (0x0982 = 0) when the PDI reads 0x098E/0x098F.
void DcUnit::pulse(const SyncUnit::Pulse& p) noexcept {
  if (p.signal == 0 && sync0_inhibited_) return;  // fault sync0_stopped: the pulse never comes out
  if (sync_level_[p.signal] && !acknowledge_mode()) {
    set_sync_level_at_system(p.signal, false, std::min(pulse_end_[p.signal], p.time));
  }
  al_events_ |= p.signal == 0 ? kAlEventSync0 : kAlEventSync1;
  pulse_end_[p.signal] = p.time + load_le<std::uint16_t>(&regs_[kSyncPulseLength]) * kPulseLengthUnitNs;
  if (!sync_level_[p.signal]) set_sync_level_at_system(p.signal, true, p.time);
}

void DcUnit::set_sync_level(unsigned signal, bool level, Nanoseconds t) noexcept {
  sync_level_[signal] = level;
  if (observer_ != nullptr) observer_->on_sync(signal, level, t);
}

// Only the observer needs the edge's true time: without one it is not
// computed (LocalClock::when, ~70 instructions; a pulse a drive and DC
// cycle, issue 30).
void DcUnit::set_sync_level_at_system(unsigned signal, bool level, std::uint64_t system) noexcept {
  sync_level_[signal] = level;
  if (observer_ != nullptr) observer_->on_sync(signal, level, when_system(system));
}

void DcUnit::end_pulses(std::uint64_t system_now) noexcept {
  if (acknowledge_mode()) return;
  for (unsigned s = 0; s < kSyncSignals; ++s) {
    if (sync_level_[s] && pulse_end_[s] <= system_now) set_sync_level_at_system(s, false, pulse_end_[s]);
  }
}

Nanoseconds DcUnit::advance(Nanoseconds now) noexcept {
  // No pulse scheduled and no output high: nothing below would act and no
  // deadline would come out (issue 8: most ESCs of a line, every cycle).
  if (!active()) {
    wake_ = kNoDeadline;
    return wake_;
  }
  const std::uint64_t system = system_time(now);
  const std::optional<std::uint64_t> next = sync_.advance(system, *this);
  end_pulses(system);
  std::optional<Nanoseconds> deadline;
  if (next) deadline = when_system(*next);
  if (!acknowledge_mode()) {
    for (unsigned s = 0; s < kSyncSignals; ++s) {
      if (!sync_level_[s]) continue;
      const Nanoseconds end = when_system(pulse_end_[s]);
      if (!deadline || end < *deadline) deadline = end;
    }
  }
  wake_ = deadline.value_or(kNoDeadline);
  return wake_;
}

void DcUnit::set_latch_input(unsigned unit, bool level, Nanoseconds t) noexcept {
  if (unit >= kLatchInputs) return;
  last_t_ = std::max(last_t_, t);
  if (latches_[unit].input(level, system_time(t))) update_latch_events();
}

// Latch events go to the owner: ECAT event 0x0210 bit 0 or AL event 0x0220 bit 1.
void DcUnit::update_latch_events() noexcept {
  constexpr std::array<std::uint8_t, kLatchInputs> kOwnerPdi{kLatch0OwnerPdi, kLatch1OwnerPdi};
  al_events_ &= ~kAlEventLatch;
  ecat_events_ = static_cast<std::uint16_t>(ecat_events_ & ~kEcatEventLatch);
  for (unsigned l = 0; l < kLatchInputs; ++l) {
    if (!latches_[l].event_pending()) continue;
    if ((regs_[kCyclicUnitControl] & kOwnerPdi[l]) != 0) {
      al_events_ |= kAlEventLatch;
    } else {
      ecat_events_ = static_cast<std::uint16_t>(ecat_events_ | kEcatEventLatch);
    }
  }
}

}  // namespace ecat::esc
