// DC register block: routing of reads and writes (ESC datasheet Section II
// §10; esc-registers.md §10). SYNC/LATCH timing is in dc_unit_sync.cpp.
#include "esc/dc/dc_unit.hpp"

#include <algorithm>

#include "common/le.hpp"
#include "esc/dc/dc_registers.hpp"

namespace ecat::esc {
namespace {

using namespace dcreg;

constexpr std::uint16_t kU16 = 2;
constexpr std::uint16_t kU32 = 4;
constexpr std::uint16_t kU64 = 8;

bool touches(std::uint16_t first, std::uint16_t end, std::uint16_t reg, std::uint16_t size) noexcept {
  return first < reg + size && reg < end;
}

}  // namespace

std::uint64_t DcUnit::offset() const noexcept { return load_le<std::uint64_t>(&regs_[kSystemTimeOffset]); }
std::uint32_t DcUnit::delay() const noexcept { return load_le<std::uint32_t>(&regs_[kSystemTimeDelay]); }
bool DcUnit::acknowledge_mode() const noexcept { return load_le<std::uint16_t>(&regs_[kSyncPulseLength]) == 0; }

void DcUnit::reset(std::uint16_t sync_pulse_length) noexcept {
  regs_.fill(0);
  store_le(&regs_[kSyncPulseLength], sync_pulse_length);
  store_le(&regs_[kSpeedCounterStart], kSpeedCounterStartReset);
  regs_[kSystemTimeDiffFilterDepth] = kSystemTimeDiffFilterDepthReset;
  regs_[kSpeedCounterFilterDepth] = kSpeedCounterFilterDepthReset;
  loop_.restart(kSpeedCounterStartReset);
  loop_.set_filter_depth(kSystemTimeDiffFilterDepthReset);
  clock_.set_rate_correction(last_t_, 0.0);
  sync_.reset();
  for (auto& l : latches_) l.reset();
  receive_latch_armed_ = false;
  sync_level_ = {};
  pulse_end_ = {};
  al_events_ = 0;
  ecat_events_ = 0;
  wake_ = Nanoseconds::min();
}

// Current values of the registers that are not plain storage, only those
// the read covers: a firmware in DC mode reads 0x098E (the SYNC0
// acknowledge) and 0x0990 every cycle, and building the whole block for
// each (the system time, the loop's registers rounded, the latches) cost
// ~400 instructions a drive and cycle (issue 30; docs/performance-log.md
// "Session 31").
void DcUnit::render(std::span<std::uint8_t, kSize> view, Nanoseconds t, Side side, std::uint16_t first,
                    std::uint16_t end) const noexcept {
  std::copy(regs_.begin() + first, regs_.begin() + end, view.begin() + first);
  const auto covers = [first, end](std::uint16_t reg, std::uint16_t size) { return touches(first, end, reg, size); };
  // 0x0910: ECAT reads see the time the frame passed the reference clock.
  if (covers(kSystemTime, kU64)) store_le(&view[kSystemTime], system_time(t) - (side == Side::Ecat ? delay() : 0u));
  if (covers(kSystemTimeDifference, kU32)) store_le(&view[kSystemTimeDifference], loop_.difference_register());
  if (covers(kSpeedCounterDiff, kU16)) store_le(&view[kSpeedCounterDiff], loop_.speed_counter_diff_register());
  if (covers(kActivationStatus, 1)) view[kActivationStatus] = sync_.activation_status();
  if (covers(kSync0Status, 1)) view[kSync0Status] = sync_level_[0] ? 1 : 0;
  if (covers(kSync1Status, 1)) view[kSync1Status] = sync_level_[1] ? 1 : 0;
  if (sync_.active() && covers(kStartTimeCyclicOperation, kU64)) {
    store_le(&view[kStartTimeCyclicOperation], sync_.next_sync0());
  }
  if (covers(kNextSync1Pulse, kU64)) store_le(&view[kNextSync1Pulse], sync_.next_sync1());
  if (covers(kLatch0Status, 1)) view[kLatch0Status] = latches_[0].status();
  if (covers(kLatch1Status, 1)) view[kLatch1Status] = latches_[1].status();
  if (covers(kLatch0TimePositive, kU64)) store_le(&view[kLatch0TimePositive], latches_[0].positive_time());
  if (covers(kLatch0TimeNegative, kU64)) store_le(&view[kLatch0TimeNegative], latches_[0].negative_time());
  if (covers(kLatch1TimePositive, kU64)) store_le(&view[kLatch1TimePositive], latches_[1].positive_time());
  if (covers(kLatch1TimeNegative, kU64)) store_le(&view[kLatch1TimeNegative], latches_[1].negative_time());
}

void DcUnit::read(std::uint16_t offset, std::span<std::uint8_t> out, Nanoseconds t, Side side) noexcept {
  last_t_ = std::max(last_t_, t);
  if (offset >= kSize) return;
  const auto n = static_cast<std::uint16_t>(std::min<std::size_t>(out.size(), kSize - offset));
  if (offset >= kSystemTime && offset + n <= kSystemTime + kU64) {
    // The system time alone (the ARMW/FRMW of every DC cycle): the same
    // value render() puts there, without building the whole block.
    std::array<std::uint8_t, kU64> value{};
    store_le(value.data(), system_time(t) - (side == Side::Ecat ? delay() : 0u));
    std::copy_n(value.begin() + (offset - kSystemTime), n, out.begin());
  } else if (offset >= kSync0Status && offset + n <= kSync0Status + kSyncSignals) {
    // SYNC0/SYNC1 status alone (a firmware's acknowledge in DC mode, every
    // cycle): the outputs' levels, as render() puts them there.
    for (std::uint16_t i = 0; i < n; ++i) out[i] = sync_level_[offset - kSync0Status + i] ? 1 : 0;
  } else {
    std::array<std::uint8_t, kSize> view;  // only [offset, offset + n) is read back
    render(view, t, side, offset, static_cast<std::uint16_t>(offset + n));
    std::copy_n(view.begin() + offset, n, out.begin());
  }
  after_read(offset, static_cast<std::uint16_t>(offset + n), side, t);
}

// Read side effects: SYNC acknowledge (PDI reads 0x098E/F) and latch events
// (the owner reads a latch time register). A read of neither (the system
// time of every ARMW, 0x0990) has none: the latch events' routing follows
// 0x0980 as it is written (after_write), not at the next read.
void DcUnit::after_read(std::uint16_t first, std::uint16_t end, Side side, Nanoseconds t) noexcept {
  constexpr std::uint16_t kLatchTimesEnd = kLatch1TimeNegative + kU64;
  if (side == Side::Pdi && touches(first, end, kSync0Status, static_cast<std::uint16_t>(kSyncSignals))) {
    for (unsigned s = 0; s < kSyncSignals; ++s) {
      if (!touches(first, end, static_cast<std::uint16_t>(kSync0Status + s), 1)) continue;
      al_events_ &= ~(s == 0 ? kAlEventSync0 : kAlEventSync1);
      if (acknowledge_mode() && sync_level_[s]) set_sync_level(s, false, t);
    }
  }
  // The latch events change only where a latch time is read (set_latch_input
  // and after_write keep them up to date otherwise).
  if (!touches(first, end, kLatch0TimePositive, kLatchTimesEnd - kLatch0TimePositive)) return;
  constexpr std::array<std::uint8_t, kLatchInputs> kOwnerPdi{kLatch0OwnerPdi, kLatch1OwnerPdi};
  constexpr std::array<std::uint16_t, kLatchInputs> kPositive{kLatch0TimePositive, kLatch1TimePositive};
  constexpr std::array<std::uint16_t, kLatchInputs> kNegative{kLatch0TimeNegative, kLatch1TimeNegative};
  for (unsigned l = 0; l < kLatchInputs; ++l) {
    const bool owner_pdi = (regs_[kCyclicUnitControl] & kOwnerPdi[l]) != 0;
    if (owner_pdi != (side == Side::Pdi)) continue;
    if (touches(first, end, kPositive[l], kU64)) latches_[l].positive_read();
    if (touches(first, end, kNegative[l], kU64)) latches_[l].negative_read();
  }
  update_latch_events();
}

bool DcUnit::writable(std::uint16_t offset, Side side) const noexcept {
  const bool ecat = side == Side::Ecat;
  const bool sync_owner = ((regs_[kCyclicUnitControl] & kSyncOwnerPdi) != 0) == !ecat;
  if (offset >= kSystemTimeOffset && offset < kSystemTimeDifference) return ecat;  // offset, delay
  if (offset == kSpeedCounterStart || offset == kSpeedCounterStart + 1) return ecat;
  if (offset == kSystemTimeDiffFilterDepth || offset == kSpeedCounterFilterDepth) return ecat;
  if (offset == kCyclicUnitControl) return ecat;
  if (offset == kActivation) return sync_owner;
  if (offset >= kStartTimeCyclicOperation && offset < kStartTimeCyclicOperation + kU64) return sync_owner;
  if (offset >= kSync0CycleTime && offset < kSync1CycleTime + kU32) return sync_owner;
  if (offset == kLatch0Control) return ((regs_[kCyclicUnitControl] & kLatch0OwnerPdi) != 0) == !ecat;
  if (offset == kLatch1Control) return ((regs_[kCyclicUnitControl] & kLatch1OwnerPdi) != 0) == !ecat;
  return false;
}

void DcUnit::write(std::uint16_t offset, std::span<const std::uint8_t> in, Nanoseconds t, Side side) noexcept {
  last_t_ = std::max(last_t_, t);
  // With a pulse scheduled or an output high, the write may move the
  // deadline (its schedule, or the clock through the time loop or the
  // offset): poll again. A write that schedules one says so itself
  // (activation_written).
  if (active()) wake_ = Nanoseconds::min();
  if (offset >= kSize) return;
  const auto n = static_cast<std::uint16_t>(std::min<std::size_t>(in.size(), kSize - offset));
  const auto end = static_cast<std::uint16_t>(offset + n);
  if (side == Side::Ecat && touches(offset, end, kReceiveTimePort0, kU32)) latch_receive_times(t);
  if (side == Side::Ecat && offset <= kSystemTime && end > kSystemTime) {
    compare_system_time(in.subspan(kSystemTime - offset, std::min<std::size_t>(kU64, end - kSystemTime)), t);
  }
  // A write inside the system time (the ARMW/FRMW of every DC cycle) stores
  // no byte and touches no register with a write effect: only the comparison
  // above (issue 8: the per-byte loop below is most of such a write's cost).
  if (offset >= kSystemTime && end <= kSystemTime + kU64) return;
  for (std::uint16_t i = 0; i < n; ++i) {
    const auto o = static_cast<std::uint16_t>(offset + i);
    if (writable(o, side)) regs_[o] = in[i];
  }
  after_write(offset, end, t);
}

void DcUnit::after_write(std::uint16_t first, std::uint16_t end, Nanoseconds t) noexcept {
  if (touches(first, end, kSpeedCounterStart, 2)) {
    loop_.restart(load_le<std::uint16_t>(&regs_[kSpeedCounterStart]));
    clock_.set_rate_correction(t, 0.0);
  }
  if (touches(first, end, kSystemTimeDiffFilterDepth, 1)) loop_.set_filter_depth(regs_[kSystemTimeDiffFilterDepth]);
  if (touches(first, end, kLatch0Control, 1)) latches_[0].set_control(regs_[kLatch0Control]);
  if (touches(first, end, kLatch1Control, 1)) latches_[1].set_control(regs_[kLatch1Control]);
  // The latch events go to the owner 0x0980 names now (Section II 0x0980 bits 4/5).
  if (touches(first, end, kCyclicUnitControl, 1) || touches(first, end, kLatch0Control, kLatchInputs)) {
    update_latch_events();
  }
  if (touches(first, end, kStartTimeCyclicOperation, kU64)) start_time_written(first, end, t);
  if (touches(first, end, kActivation, 1)) activation_written(t);
}

// Section II 0x0900: an ECAT write latches the local time of this frame at
// every port; port 0 and the processing unit now, the others as the frame
// comes back through them (on_frame_arrival).
void DcUnit::latch_receive_times(Nanoseconds t) noexcept {
  const std::uint64_t local = clock_.at(t);
  store_le(&regs_[kReceiveTimePort0], static_cast<std::uint32_t>(local));
  store_le(&regs_[kReceiveTimeProcessingUnit], local);
  receive_latch_armed_ = true;
  for (unsigned p = 1; p < kPorts; ++p) {
    if (early_mask_ & (1u << p)) latch_return_time(static_cast<int>(p), early_[p]);
  }
  early_mask_ = 0;
}

void DcUnit::latch_return_time(int port, Nanoseconds t) noexcept {
  const auto reg = static_cast<std::uint16_t>(kReceiveTimePort0 + port * kReceiveTimePortStride);
  store_le(&regs_[reg], static_cast<std::uint32_t>(clock_.at(t)));
}

// Section II 0x0910 write: compare the written value with the copy latched
// at SOF (minus the delay: what the reference showed when the frame passed
// it). A 4-byte write compares the low 32 bits.
void DcUnit::compare_system_time(std::span<const std::uint8_t> written, Nanoseconds t) noexcept {
  // The local time once: the copy and the time loop both need it.
  const std::uint64_t local = clock_.at(t);
  const std::uint64_t copy = local + offset() - delay();
  // The written bytes over the low bytes of the copy, in a register: built
  // in an 8-byte buffer by narrower stores and read back whole, it stalled
  // the load at every ARMW/FRMW of the time (issue 30).
  std::uint64_t value = copy;
  if (written.size() == kU64) {
    value = load_le<std::uint64_t>(written.data());
  } else {
    for (std::size_t i = 0; i < written.size(); ++i) {
      const unsigned shift = static_cast<unsigned>(i) * 8u;
      value = (value & ~(std::uint64_t{0xFF} << shift)) | (std::uint64_t{written[i]} << shift);
    }
  }
  std::int64_t difference = 0;
  if (written.size() > kU32) {
    difference = static_cast<std::int64_t>(copy - value);
  } else {
    difference = static_cast<std::int32_t>(static_cast<std::uint32_t>(copy) - static_cast<std::uint32_t>(value));
  }
  loop_.compare(difference, t, local, clock_);
}

}  // namespace ecat::esc
