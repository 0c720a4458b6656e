// SYNC0/SYNC1 generation; behaviour in sync_unit.hpp.
#include "esc/dc/sync_unit.hpp"

#include "esc/dc/dc_registers.hpp"

namespace ecat::esc {

void SyncUnit::reset() noexcept {
  s_ = {};
  active_ = false;
  next0_.reset();
  next1_.reset();
  sync1_anchor_ = 0;
  status_ = 0;
}

bool SyncUnit::sync0_out() const noexcept { return (s_.activation & dcreg::kActivateSync0) != 0; }
bool SyncUnit::sync1_out() const noexcept { return (s_.activation & dcreg::kActivateSync1) != 0; }

// Section II 0x0981/0x0984: the start time must lie in the "near future";
// otherwise the unit waits for the 64-bit time to wrap - unless the
// plausibility check (bit 5) is on, which fires at once and flags 0x0984 bit 2.
void SyncUnit::activate(const SyncSettings& s, std::uint64_t now) noexcept {
  s_ = s;
  active_ = true;
  status_ = 0;
  next0_.reset();
  next1_.reset();
  if (!sync0_out() && !sync1_out()) return;
  if (sync0_out()) status_ |= dcreg::kFirstSync0Pending;
  if (sync1_out()) status_ |= dcreg::kFirstSync1Pending;
  const std::uint64_t near = (s.activation & dcreg::kNearFutureShort) != 0 ? kNearFutureShort : kNearFutureLong;
  const std::uint64_t ahead = s.start_time - now;
  std::uint64_t start = s.start_time;
  if (ahead == 0 || ahead >= near) {
    if ((s.activation & dcreg::kStartTimePlausibility) == 0) return;  // waits for the wrap
    status_ |= dcreg::kStartTimeOutOfNearFuture;
    start = now;
  }
  next0_ = start;
  sync1_anchor_ = start;
}

void SyncUnit::deactivate() noexcept {
  active_ = false;
  next0_.reset();
  next1_.reset();
  status_ = 0;
}

void SyncUnit::debug_pulse(std::uint64_t now, Sink& sink) noexcept {
  if (sync0_out()) sink.pulse({0, now});
  if (sync1_out()) sink.pulse({1, now});
}

void SyncUnit::sync0_tick(std::uint64_t t, Sink& sink) noexcept {
  if (sync0_out()) {
    sink.pulse({0, t});
    status_ &= static_cast<std::uint8_t>(~dcreg::kFirstSync0Pending);
  }
  const std::uint32_t c0 = s_.sync0_cycle;
  const std::uint32_t c1 = s_.sync1_cycle;
  if (sync1_out()) {
    if (c1 == 0) {
      sink.pulse({1, t});
      status_ &= static_cast<std::uint8_t>(~dcreg::kFirstSync1Pending);
    } else if (c0 == 0 || c1 < c0) {
      next1_ = t + c1;  // shifted from this SYNC0
    } else if (t - sync1_anchor_ >= c1) {
      sink.pulse({1, t});  // multiple of SYNC0
      status_ &= static_cast<std::uint8_t>(~dcreg::kFirstSync1Pending);
      sync1_anchor_ = t;
    }
  }
  if (c0 == 0) {
    next0_.reset();  // single shot
  } else {
    next0_ = t + c0;
  }
}

std::optional<std::uint64_t> SyncUnit::advance(std::uint64_t now, Sink& sink) noexcept {
  for (unsigned n = 0; n < kMaxPulsesPerAdvance; ++n) {
    const bool due0 = next0_ && *next0_ <= now;
    const bool due1 = next1_ && *next1_ <= now;
    if (!due0 && !due1) break;
    if (due1 && (!due0 || *next1_ <= *next0_)) {
      sink.pulse({1, *next1_});
      status_ &= static_cast<std::uint8_t>(~dcreg::kFirstSync1Pending);
      next1_.reset();
    } else {
      sync0_tick(*next0_, sink);
    }
  }
  // Too far behind (poll() not called for a long time): skip the rest.
  if (next0_ && *next0_ <= now && s_.sync0_cycle != 0) {
    const std::uint64_t behind = now - *next0_;
    *next0_ += (behind / s_.sync0_cycle + 1) * s_.sync0_cycle;
    sync1_anchor_ = *next0_;
    next1_.reset();
  }
  if (next0_ && next1_) return *next0_ < *next1_ ? *next0_ : *next1_;
  if (next0_) return next0_;
  return next1_;
}

std::uint64_t SyncUnit::next_sync0() const noexcept { return next0_ ? *next0_ : s_.start_time; }

std::uint64_t SyncUnit::next_sync1() const noexcept {
  if (next1_) return *next1_;
  if (!sync1_out() || !next0_) return 0;
  const std::uint32_t c0 = s_.sync0_cycle;
  const std::uint32_t c1 = s_.sync1_cycle;
  if (c1 == 0) return *next0_;
  if (c0 == 0 || c1 < c0) return *next0_ + c1;
  const std::uint64_t target = sync1_anchor_ + c1;
  if (target <= *next0_) return *next0_;
  return *next0_ + (target - *next0_ + c0 - 1) / c0 * c0;
}

}  // namespace ecat::esc
