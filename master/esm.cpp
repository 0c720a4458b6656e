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

Expected<AlStatus, MasterError> Master::poll_state(std::size_t slave, std::uint8_t wanted, bool ack) {
  AlStatus last;
  bool seen = false;
  for (PollBudget budget(clock_, config_.state_timeout, config_.max_polls); budget.next();) {
    auto s = read_al_status(slave);
    if (!s) return fail(s.error());
    last = *s;
    seen = true;
    // Refused (or an earlier error not acknowledged). When this request
    // acknowledges, the error may still be the old one: a µC that polls
    // takes the request some time after the write (docs/pdi-host.md).
    if (last.error() && !ack) return last;
    if (!last.error() && last.state() == wanted) return last;
  }
  if (ack && seen && last.error()) return last;  // the acknowledge was refused
  return fail(MasterError::StateTimeout);
}

Expected<AlStatus, MasterError> Master::write_al_control(std::size_t slave, std::uint16_t value) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  // Without device emulation AL control is a one-deep mailbox: after an
  // ECAT write the ESC refuses the next one (WKC 0) until the slave's µC
  // has read it (Section II 0x0120). A µC that polls may not have read the
  // previous request yet: write again until it takes it, within the state
  // timeout (docs/pdi-host.md: a firmware in another process shows it).
  Expected<void, MasterError> written = fail(MasterError::WorkingCounter);
  for (PollBudget budget(clock_, config_.state_timeout, config_.max_polls); budget.next();) {
    written = fpwr_u16(slaves_[slave].station_address, reg::kAlControl, value);
    if (written || written.error() != MasterError::WorkingCounter) break;
  }
  if (!written) return fail(written.error());
  return poll_state(slave, static_cast<std::uint8_t>(value & kAlStateMask), (value & kAlErrorBit) != 0);
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

// Broadcast first (SOEM ecx_writestate(0), IgH): one BWR of AL control to
// every slave, then BRDs of AL status until every slave shows the state.
// The ORed status byte equals the state code only if every slave is in it
// without ErrInd (the codes are single bits; Boot = 3 is not, so it goes
// slave by slave), and the WKC says all answered. A refusal or a timeout
// falls back to slave by slave, which names the slave and its 0x0134 code.
// 1000 slaves: a few frames per state instead of 4 per slave (issue 16 item 5).
Expected<void, MasterError> Master::request_state_all(AlState state) {
  const auto code = static_cast<std::uint8_t>(state);
  if (state != AlState::Boot && !slaves_.empty()) {
    const std::uint8_t control[2]{code, 0};
    auto w = bwr(reg::kAlControl, control);
    if (w && *w == slaves_.size()) {
      for (PollBudget budget(clock_, config_.state_timeout, config_.max_polls); budget.next();) {
        std::uint8_t status[2]{};
        auto wkc = link_.exchange(Command::Brd, device_address(0, reg::kAlStatus), Bytes(status, sizeof status));
        if (!wkc) return fail(wkc.error());
        if ((status[0] & kAlErrorBit) != 0) break;  // someone refused: find who
        if (*wkc == slaves_.size() && (status[0] & kAlStateMask) == code) {
          for (auto& s : slaves_) s.al = AlStatus{code, 0};
          return {};
        }
      }
    }
  }
  for (std::size_t i = 0; i < slaves_.size(); ++i) {
    auto s = request_state(i, state);
    if (!s) return fail(s.error());
    if (s->error()) return fail(MasterError::StateTimeout);
  }
  return {};
}

}  // namespace ecat::master
