// ESM requests the way IgH/SOEM do them (masters.md §2.5, esm-al-codes.md §5):
// write AL control 0x0120, poll 0x0130 (6 bytes, status + code 0x0134) until
// the requested state without ErrInd (reached) or ErrInd set (refused).
#include "master/master.hpp"
#include "master/poll_budget.hpp"
#include "master/registers.hpp"

namespace ecat::master {

Expected<AlStatus, MasterError> Master::read_al_status(std::size_t slave) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  std::uint8_t b[reg::kAlStatusReadLength]{};
  if (auto r = fprd(slaves_[slave].station_address, reg::kAlStatus, b); !r) return fail(r.error());
  AlStatus s;
  s.raw = load_le<std::uint16_t>(b);
  s.code = load_le<std::uint16_t>(b + (reg::kAlStatusCode - reg::kAlStatus));
  slaves_[slave].al = s;
  return s;
}

Expected<AlStatus, MasterError> Master::poll_state(std::size_t slave, std::uint8_t wanted) {
  AlStatus last;
  for (PollBudget budget(clock_, config_.state_timeout, config_.max_polls); budget.next();) {
    auto s = read_al_status(slave);
    if (!s) return fail(s.error());
    last = *s;
    if (last.error()) return last;  // refused (or an earlier error not acknowledged)
    if (last.state() == wanted) return last;
  }
  return fail(MasterError::StateTimeout);
}

Expected<AlStatus, MasterError> Master::write_al_control(std::size_t slave, std::uint16_t value) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  if (auto r = fpwr_u16(slaves_[slave].station_address, reg::kAlControl, value); !r) return fail(r.error());
  return poll_state(slave, static_cast<std::uint8_t>(value & kAlStateMask));
}

Expected<AlStatus, MasterError> Master::request_state(std::size_t slave, AlState state, bool ack) {
  const auto value = static_cast<std::uint16_t>(static_cast<std::uint8_t>(state) | (ack ? kAlErrorBit : 0));
  return write_al_control(slave, value);
}

Expected<AlStatus, MasterError> Master::acknowledge_error(std::size_t slave) {
  auto s = read_al_status(slave);
  if (!s) return fail(s.error());
  if (!s->error()) return *s;
  const auto value = static_cast<std::uint16_t>(s->state() | kAlErrorBit);
  if (auto r = fpwr_u16(slaves_[slave].station_address, reg::kAlControl, value); !r) return fail(r.error());
  for (PollBudget budget(clock_, config_.state_timeout, config_.max_polls); budget.next();) {
    auto now = read_al_status(slave);
    if (!now) return fail(now.error());
    if (!now->error()) return *now;
  }
  return fail(MasterError::StateTimeout);
}

Expected<void, MasterError> Master::request_state_all(AlState state) {
  for (std::size_t i = 0; i < slaves_.size(); ++i) {
    auto s = request_state(i, state);
    if (!s) return fail(s.error());
    if (s->error()) return fail(MasterError::StateTimeout);
  }
  return {};
}

}  // namespace ecat::master
