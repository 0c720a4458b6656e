#include "apps/ecat-master/session.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstdio>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "apps/ecat-master/cia402_motion.hpp"
#include "apps/ecat-master/error_text.hpp"
#include "common/frame.hpp"
#include "common/le.hpp"
#include "master/registers.hpp"
#include "apps/ecat-master/topology_report.hpp"

namespace ecat::app {
namespace {

constexpr unsigned kBitsPerByte = 8;
// Cycles exchanged in SafeOp before Op is requested, so the slaves have seen
// valid outputs (SM2 written, watchdog triggered) when they check SafeOp->Op.
constexpr unsigned kSafeOpWarmupCycles = 10;
// With the DC phase lock, SafeOp runs long enough for the lock to acquire and
// settle (dc_phase_test: |phase error| < 1 us after ~150 frames) before Op,
// where a late frame counts as a missed SM event.
constexpr unsigned kSafeOpPhaseLockCycles = 300;
// Op requested with the cycle running: the cycles it waits at least (and
// at least the master's state timeout).
constexpr unsigned kOpRequestCycles = 3000;
constexpr unsigned kDcDriftIterations = 1000;
constexpr std::uint16_t kSyncManagerOutputsParameter = 0x1C32;
constexpr std::uint16_t kSyncManagerInputsParameter = 0x1C33;
constexpr std::uint8_t kSyncModeSub = 1;
constexpr std::uint16_t kSyncModeDcSync0 = 2;
constexpr Nanoseconds kSync0StartDelay = std::chrono::milliseconds(20);
constexpr std::uint64_t kStateCheckInterval = 500;
constexpr std::uint64_t kRecoverCheckInterval = 100;
constexpr std::uint16_t kSupportedDriveModes = 0x6502;
constexpr std::uint32_t kSupportsCsp = 1u << 7;
constexpr std::uint16_t kModesOfOperation = 0x6060;
constexpr std::uint8_t kCyclicSynchronousPosition = 8;

// The SII's process-data SMs are SM2 (outputs) and SM3 (inputs) at most.
bool standard_process_sms(const master::SiiInfo& sii) {
  constexpr std::size_t kOutputSm = 2, kInputSm = 3;
  for (std::size_t n = 0; n < sii.sync_managers.size(); ++n) {
    const std::uint8_t t = sii.sync_managers[n].type;
    if (t == master::sii::kSmTypeOutputs && n != kOutputSm) return false;
    if (t == master::sii::kSmTypeInputs && n != kInputSm) return false;
  }
  return true;
}

Nanoseconds percentile(std::vector<Nanoseconds>& v, double p) {
  if (v.empty()) return Nanoseconds{0};
  const auto k = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

Expected<void, std::string> Session::configure_slave(std::size_t i, bool again) {
  auto& s = master_.slave(i);
  has_coe_[i] = s.sii.has_coe();
  // Every slave goes through PreOp (ETG.1000.6 §6.4.1: Init->SafeOp is not a
  // transition, 0x0011); only a slave with a mailbox has its SM0/SM1 set up
  // first. Couplers (EK1100) and plain I/O have none.
  if (s.sii.has_mailbox()) {
    if (auto ok = master_.configure_mailbox(i); !ok) {
      return fail(fmt::format("slave {}: mailbox set-up: {}", i + 1, error_text(ok.error())));
    }
  }
  auto st = master_.request_state(i, master::AlState::PreOp);
  if (!st) return fail(fmt::format("slave {}: PreOp: {}", i + 1, error_text(st.error())));
  if (st->error()) return fail(fmt::format("slave {}: PreOp refused, AL status code 0x{:04X}", i + 1, st->code));
  // Without CoE the SII's PDOs size every process-data SM (SOEM ecx_map_sii).
  if (!has_coe_[i]) {
    master_.size_process_data_from_sii(i);
    return {};
  }
  master::CoeClient coe(master_, i);
  auto pdos = PdoLocator::read(coe);
  if (!pdos) return fail(fmt::format("slave {}: {}", i + 1, pdos.error()));
  pdos_[i] = std::move(*pdos);
  for (const auto& [index, sub] : again ? decltype(o_.sdo_reads){} : o_.sdo_reads) {
    auto v = coe.upload(index, sub);
    if (!v) return fail(fmt::format("slave {}: SDO upload {:04X}h:{:02X}: {}", i + 1, index, sub, error_text(v.error())));
    fmt::print("slave {} sdo {:04X}h:{:02X} = {:02X}\n", i + 1, index, sub, fmt::join(*v, " "));
  }
  auto bits = [](const std::vector<MappedObject>& side) {
    std::uint32_t n = 0;
    for (const auto& m : side) n += m.bits;
    return n;
  };
  s.pd.output_bytes = static_cast<std::uint16_t>((bits(pdos_[i].outputs) + kBitsPerByte - 1) / kBitsPerByte);
  s.pd.input_bytes = static_cast<std::uint16_t>((bits(pdos_[i].inputs) + kBitsPerByte - 1) / kBitsPerByte);
  s.pd.per_sm = false;
  // Process data on other SMs than SM2 outputs / SM3 inputs, or on more
  // than one per direction: each SM from its 1C10h+n (ETG.1000.6 §5.6.7.4.2).
  if (!standard_process_sms(s.sii)) {
    if (auto ok = coe.read_pdo_sizes(); !ok) {
      return fail(fmt::format("slave {}: PDO sizes per SM: {}", i + 1, error_text(ok.error())));
    }
  }
  if (o_.move) {
    // CSP needs 6502h bit 7 (CiA402 §6.2.1); a drive without it is left alone.
    auto modes = coe.upload_value(kSupportedDriveModes, 0);
    csp_[i] = modes && (*modes & kSupportsCsp) != 0;
    if (csp_[i] && !pdos_[i].output_byte(kModesOfOperation)) {
      if (auto ok = coe.download_value(kModesOfOperation, 0, kCyclicSynchronousPosition, 1); !ok) {
        return fail(fmt::format("slave {}: 6060h = 8: {}", i + 1, error_text(ok.error())));
      }
    }
  }
  if (o_.dc && s.esc.has_dc()) {
    for (std::uint16_t obj : {kSyncManagerOutputsParameter, kSyncManagerInputsParameter}) {
      auto mode = coe.upload_value(obj, kSyncModeSub);
      if (mode && *mode == kSyncModeDcSync0) continue;
      auto ok = coe.download_value(obj, kSyncModeSub, kSyncModeDcSync0, 2);
      // A read-only sync mode follows the DC activation 0x0981 (ETG.1020
      // §22.2): the Sync0 set-up below selects it.
      if (!ok && !(ok.error().from_slave && ok.error().code == master::SdoAbortCode::ReadOnly)) {
        return fail(fmt::format("slave {}: {:04X}h:01 = DC Sync0: {}", i + 1, obj, error_text(ok.error())));
      }
    }
  }
  return {};
}

Expected<void, std::string> Session::bring_up() {
  auto n = master_.scan();
  if (!n) return fail(fmt::format("scan: {}", error_text(n.error())));
  if (o_.expect_slaves != 0 && *n != o_.expect_slaves) {
    return fail(fmt::format("scan found {} slave(s), expected {}", *n, o_.expect_slaves));
  }
  report_.slaves = *n;
  if (o_.scan_only && o_.dc) {
    // --scan --dc: measure the propagation delays too (latch the port
    // receive times, write 0x0920/0x0928) and print them; no AL state moves.
    auto dc = master_.configure_dc(clock_.now());
    if (!dc) return fail(fmt::format("DC set-up: {}", error_text(dc.error())));
    std::fputs(topology_report(master_, true).c_str(), stdout);
    return {};
  }
  if (o_.topology || o_.scan_only) std::fputs(topology_report(master_, false).c_str(), stdout);
  if (o_.scan_only) return {};
  pdos_.assign(*n, {});
  has_coe_.assign(*n, false);
  csp_.assign(*n, false);
  for (std::size_t i = 0; i < *n; ++i) {
    const auto& s = master_.slave(i);
    if (o_.verbose) {
      std::printf("slave %zu: station 0x%04X vendor 0x%08X product 0x%08X rev 0x%08X \"%s\"\n", i + 1,
                  s.station_address, s.sii.vendor_id, s.sii.product_code, s.sii.revision,
                  s.sii.device_name().c_str());
    }
    if (auto ok = configure_slave(i); !ok) return ok;
  }
  if (auto ok = master_.configure_process_data(); !ok) {
    return fail(fmt::format("process data set-up: {}", error_text(ok.error())));
  }
  if (o_.dc) {
    auto dc = master_.configure_dc(clock_.now());
    if (!dc) return fail(fmt::format("DC set-up: {}", error_text(dc.error())));
    if (auto ok = master_.dc_static_drift_compensation(kDcDriftIterations); !ok) {
      return fail(fmt::format("DC drift compensation: {}", error_text(ok.error())));
    }
    std::optional<std::uint64_t> sync0_start;
    if (o_.topology) std::fputs(topology_report(master_, true).c_str(), stdout);
    for (std::size_t i = 0; i < *n; ++i) {
      if (master_.slave(i).esc.has_dc()) {
        auto start = master_.configure_sync0(i, static_cast<std::uint32_t>(o_.period.count()), 0, kSync0StartDelay);
        if (!start) return fail(fmt::format("slave {}: Sync0: {}", i + 1, error_text(start.error())));
        // Every start is a whole number of cycles (configure_sync0): one phase.
        if (!sync0_start) sync0_start = *start;
      }
    }
    if (sync0_start && o_.dc_lead.count() != 0) {
      master::DcPhaseConfig pc;
      pc.cycle = o_.period;
      pc.lead = o_.dc_lead.count() < 0 ? o_.period / 2 : o_.dc_lead;
      pc.sync0_start = *sync0_start;
      phase_.emplace(pc);
    }
  }
  for (std::size_t i = 0; i < *n; ++i) {
    auto st = master_.request_state(i, master::AlState::SafeOp);
    if (!st) return fail(fmt::format("slave {}: SafeOp: {}", i + 1, error_text(st.error())));
    if (st->error()) return fail(fmt::format("slave {}: SafeOp refused, AL status code 0x{:04X}", i + 1, st->code));
  }
  // Valid outputs before Op (ETG.1000.6 §6.4.1: SafeOp->Op checks them).
  const unsigned warmup = phase_ ? kSafeOpPhaseLockCycles : kSafeOpWarmupCycles;
  for (unsigned c = 0; c < warmup; ++c) (void)cycle_exchange();
  if (auto ok = request_op_cycling(); !ok) return ok;
  if (o_.verbose) std::printf("all %zu slave(s) in Op\n", *n);
  return {};
}

Expected<master::CyclicResult, master::MasterError> Session::cycle_exchange() {
  Nanoseconds target;
  if (phase_) {
    target = phase_->next_send(clock_.now());
  } else {
    const Nanoseconds now = clock_.now();
    if (next_fixed_.count() < 0) next_fixed_ = now;
    // More than a period behind (a stall): the missed periods are skipped,
    // not sent in a burst.
    while (next_fixed_ + o_.period <= now) {
      next_fixed_ += o_.period;
      if (record_lateness_) ++report_.skipped_slots;
    }
    target = next_fixed_;
    next_fixed_ += o_.period;
  }
  wait_(target);
  if (record_lateness_) {
    const Nanoseconds late = clock_.now() - target;
    report_.lateness.add(late);
    report_.jitter_max = std::max(report_.jitter_max, late);
  } else if (last_send_) {
    startup_gap_max_ = std::max(startup_gap_max_, clock_.now() - *last_send_);
  }
  last_send_ = clock_.now();
  auto r = master_.exchange_process_data();
  if (r && phase_ && r->reference_time) phase_->update(r->sent_at, *r->reference_time);
  return r;
}

// Op is asked of every slave at once and the cycle runs until all are in
// it, as SOEM's examples and IgH's applications do (masters.md): the
// outputs keep each slave's SM watchdog fed while the others take their
// time, and a DC slave counts SYNC0s without new outputs from its first
// cycle in Op (docs/dc.md). Asked one slave at a time with no cycle
// between (the start-up without DC until 2026-12-01), each request took a
// few frames and, on a busy host, the waits for them: beside two CPU
// burners the later of 250 drives saw no outputs for longer than their
// 100 ms SM watchdog before their turn and refused Op with 001Bh
// (docs/e2e.md "Op with the cycle running").
//
// The request: one BWR of AL control; a slave that did not take it (WKC
// short: a µC that has not read its previous request yet, 0x0120 without
// device emulation) is asked again with FPWR, one slave a cycle. The
// check: one BRD of AL status a cycle - the state bits ORed equal Op with
// WKC = every slave only when all are in Op without ErrInd; with ErrInd
// the slaves are read one by one to name the one that refused. It waits
// at least kOpRequestCycles cycles and at least the master's state timeout
// (5 s, what one slave's request_state waits): at a short period the
// cycles alone were a fraction of a second.
Expected<void, std::string> Session::request_op_cycling() {
  const auto op = static_cast<std::uint16_t>(master::AlState::Op);
  const std::size_t n = report_.slaves;
  std::uint8_t control[2];
  store_le(control, op);
  auto taken = master_.bwr(master::reg::kAlControl, control);
  if (!taken) return fail(fmt::format("Op: {}", error_text(taken.error())));
  std::size_t ask_next = *taken == n ? n : 0;  // the next slave asked by FPWR, n: none
  const Nanoseconds deadline = clock_.now() + master_.config().state_timeout;
  for (unsigned c = 0; c < kOpRequestCycles || clock_.now() < deadline; ++c) {
    (void)cycle_exchange();
    if (ask_next < n) {
      // Only a WKC error (not taken yet) is asked again; a lost frame too.
      if (master_.fpwr_u16(master_.slave(ask_next).station_address, master::reg::kAlControl, op)) ++ask_next;
      continue;
    }
    std::uint8_t status[2]{};  // 0x0130 of every slave ORed
    auto wkc = master_.transact(Command::Brd, device_address(0, master::reg::kAlStatus), status);
    if (!wkc) continue;  // a lost frame: read again next cycle
    if ((status[0] & master::kAlErrorBit) != 0) {
      for (std::size_t i = 0; i < n; ++i) {
        auto st = master_.read_al_status(i);
        if (st && st->error()) return fail(fmt::format("slave {}: Op refused, AL status code 0x{:04X}", i + 1, st->code));
      }
      continue;  // acknowledged meanwhile, or a read lost: look again
    }
    if (*wkc == n && (status[0] & master::kAlStateMask) == op) return {};
  }
  std::size_t reached = 0;
  for (std::size_t i = 0; i < n; ++i) {
    auto st = master_.read_al_status(i);
    reached += st && st->is(master::AlState::Op) && !st->error();
  }
  return fail(fmt::format("Op: {} of {} slave(s) reached it", reached, n));
}

void Session::drive_cycle(std::uint64_t cycle) {
  for (auto& m : motions_) m.cycle(cycle, o_.cycles, o_.move_distance);
}

void Session::check_states() {
  // One frame first: BRD of the AL status ORs every slave's 0x0130 (WKC =
  // slave count), so all in Op without error reads 0x08; only otherwise is
  // each slave read (one frame each would eat into the cycle).
  std::uint8_t all[2]{};
  auto wkc = master_.transact(Command::Brd, device_address(0, master::reg::kAlStatus), all);
  const auto op = static_cast<std::uint16_t>(master::AlState::Op);
  if (wkc && *wkc == report_.slaves && load_le<std::uint16_t>(all) == op) return;
  report_.left_op.resize(report_.slaves, 0);
  report_.last_code.resize(report_.slaves, 0);
  report_.reconnected.resize(report_.slaves, 0);
  for (std::size_t i = 0; i < report_.slaves; ++i) {
    auto st = master_.read_al_status(i);
    if (!st || !st->is(master::AlState::Op) || st->error()) {
      ++report_.state_errors;
      if (o_.verbose && st) {
        std::printf("slave %zu left Op: AL status 0x%04X, AL status code 0x%04X\n", i + 1, st->raw, st->code);
      }
      if (!o_.recover) continue;
      if (!st) {
        reconnect(i);
        continue;
      }
      // --recover, as SOEM's ec_sample check thread: acknowledge the error
      // (state | 0x10), and ask a slave back in SafeOp for Op; no waiting,
      // the next check sees the result.
      const std::uint16_t station = master_.slave(i).station_address;
      if (st->error()) {
        ++report_.left_op[i];
        report_.last_code[i] = st->code;
        (void)master_.fpwr_u16(station, master::reg::kAlControl,
                               static_cast<std::uint16_t>(st->state() | master::kAlErrorBit));
      } else if (st->is(master::AlState::SafeOp)) {
        (void)master_.fpwr_u16(station, master::reg::kAlControl, op);
      }
    }
  }
}

// SOEM's ec_recover_slave + ec_reconfig_slave: a slave that does not answer
// at its station address but at its position with address 0 (it was power
// cycled) is checked to be the same device, addressed, configured as at
// start-up and its process-data SMs and FMMUs written again, then asked for
// SafeOp; the next check asks for Op. Nothing answers at the position yet:
// tried again at the next check. No waiting beyond the set-up's own
// exchanges (its SDO reads are the longest part).
void Session::reconnect(std::size_t i) {
  auto back = master_.readdress(i);
  if (!back || !*back) {
    if (!back && back.error() == master::MasterError::WrongSlave) {
      std::printf("slave %zu: another device answers at its position: not configured\n", i + 1);
    }
    return;
  }
  if (o_.dc) {
    // Its DC offset, delay and SYNC0 would have to be set up again while the
    // others run: not done (docs/master.md "Hot connect").
    std::printf("slave %zu: came back at its position; not configured again with --dc\n", i + 1);
    return;
  }
  auto& s = master_.slave(i);
  const master::ProcessDataLayout layout = s.pd;
  auto ok = configure_slave(i, true);
  const bool same = s.pd.output_bytes == layout.output_bytes && s.pd.input_bytes == layout.input_bytes;
  s.pd = layout;  // the image's layout stays as configured at start-up
  if (!ok || !same) {
    std::printf("slave %zu: came back but cannot be configured again: %s\n", i + 1,
                ok ? "its process data sizes changed" : ok.error().c_str());
    return;
  }
  if (auto pd = master_.write_process_data_config(i); !pd) {
    std::printf("slave %zu: came back; process data set-up: %s\n", i + 1, error_text(pd.error()).c_str());
    return;
  }
  ++report_.reconnected[i];
  (void)master_.write_al_control(i, static_cast<std::uint16_t>(master::AlState::SafeOp));
}

Expected<SessionReport, std::string> Session::run() {
  std::vector<Nanoseconds> rtts;
  rtts.reserve(o_.cycles);
  motions_.clear();
  std::vector<std::size_t> drive_slave;
  for (std::size_t i = 0; i < report_.slaves; ++i) {
    Cia402Motion m(master_, i, pdos_[i]);
    if (has_coe_[i] && csp_[i] && m.usable()) {
      motions_.push_back(m);
      drive_slave.push_back(i);
    }
  }
  std::vector<std::int32_t> start_positions(motions_.size(), 0);
  std::vector<Nanoseconds> phase_errors;
  if (phase_) phase_errors.reserve(o_.cycles);
  const std::uint64_t missed_before = phase_ ? phase_->sync0_without_frame() : 0;
  report_.margin_min = o_.period;
  record_lateness_ = true;
  for (std::uint64_t c = 0; c < o_.cycles; ++c) {
    if (o_.stop != nullptr && *o_.stop != 0) {
      report_.stopped = true;
      break;
    }
    if (o_.move) drive_cycle(c);
    auto r = cycle_exchange();
    ++report_.cycles;
    if (r && phase_ && r->reference_time && phase_->acquired()) {
      const Nanoseconds err{std::abs(phase_->phase_error())};
      phase_errors.push_back(err);
      report_.phase_error_max = std::max(report_.phase_error_max, err);
      report_.margin_min = std::min(report_.margin_min, Nanoseconds{phase_->margin_to_sync0()});
    }
    if (!r) {
      ++report_.lost_frames;
      continue;
    }
    if (!r->ok()) ++report_.wkc_errors;
    rtts.push_back(r->round_trip);
    // A slave that left Op still counts its SM2 writes in the WKC, so the
    // state is checked too (as ethercrab does every cycle; here every
    // kStateCheckInterval cycles and after the last one).
    const std::uint64_t interval = o_.recover ? kRecoverCheckInterval : kStateCheckInterval;
    if ((c + 1) % interval == 0 || c + 1 == o_.cycles) check_states();
    if (c == 0) {
      for (std::size_t k = 0; k < motions_.size(); ++k) start_positions[k] = motions_[k].actual_position();
    }
  }
  record_lateness_ = false;
  if (phase_) {
    report_.phase_locked = true;
    report_.phase_error_p99 = percentile(phase_errors, 0.99);
    report_.sync0_without_frame = phase_->sync0_without_frame() - missed_before;
  }
  report_.rtt_median = percentile(rtts, 0.5);
  report_.rtt_p99 = percentile(rtts, 0.99);
  report_.rtt_max = rtts.empty() ? Nanoseconds{0} : *std::max_element(rtts.begin(), rtts.end());
  if (o_.move) {
    if (motions_.empty()) report_.moved_ok = false;
    for (std::size_t k = 0; k < motions_.size(); ++k) {
      const Cia402Motion& m = motions_[k];
      const std::size_t i = drive_slave[k];
      const std::int32_t moved = m.actual_position() - start_positions[k];
      report_.final_positions.push_back(m.actual_position());
      if (!m.operation_enabled() || moved < o_.move_distance / 2) report_.moved_ok = false;
      if (o_.verbose) {
        std::printf("slave %zu: statusword 0x%04X, actual position %d (moved %d increments)\n", i + 1,
                    m.statusword(), m.actual_position(), moved);
      }
    }
  }
  return report_;
}

}  // namespace ecat::app
