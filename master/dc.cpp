// Distributed clocks set-up (esc-registers.md §10, masters.md §1.3 DC, §4.3):
// BWR 0x0900 latches the port receive times in every ESC; per DC slave the
// master reads 0x0900-0x090F and 0x0918, computes the propagation delay from
// the reference clock (first DC slave) through the tree (dc_delay.hpp), writes the offset
// 0x0920 = master time - 0x0918 and the delay 0x0928. Drift compensation is
// FRMW 0x0910 from the reference clock; Sync0 via 0x0981/0x09A0/0x0990.
#include <algorithm>
#include <vector>

#include "master/dc_delay.hpp"
#include "master/master.hpp"
#include "master/registers.hpp"

namespace ecat::master {

namespace {
constexpr std::size_t kPorts = kEscPortCount;
}  // namespace

Expected<std::size_t, MasterError> Master::configure_dc(Nanoseconds master_time) {
  const std::uint8_t latch[4]{};
  if (auto r = bwr(reg::kDcPortReceiveTime, latch); !r) return fail(r.error());
  std::vector<std::size_t> dc;
  for (std::size_t i = 0; i < slaves_.size(); ++i) {
    SlaveInfo& s = slaves_[i];
    if (!s.esc.has_dc()) continue;
    dc.push_back(i);
    std::uint8_t times[4 * kPorts]{};
    if (auto r = fprd(s.station_address, reg::kDcPortReceiveTime, times); !r) return fail(r.error());
    for (std::size_t p = 0; p < kPorts; ++p) s.dc.port_receive_time[p] = load_le<std::uint32_t>(times + 4 * p);
    std::uint8_t pu[8]{};
    if (auto r = fprd(s.station_address, reg::kDcProcessingUnitReceiveTime, pu); !r) return fail(r.error());
    s.dc.processing_unit_time = load_le<std::uint64_t>(pu);
  }
  if (dc.empty()) {
    reference_clock_.reset();
    return std::size_t{0};
  }
  reference_clock_ = dc.front();
  // Entry ports from the port times, parents and parent ports from DL status
  // (topology.hpp), then the delays of the tree (dc_delay.hpp).
  std::vector<TopologyInput> in(slaves_.size());
  std::vector<std::optional<PortTimes>> times(slaves_.size());
  for (std::size_t i = 0; i < slaves_.size(); ++i) {
    in[i].dl_status = slaves_[i].dl_status;
    if (slaves_[i].esc.has_dc()) times[i] = slaves_[i].dc.port_receive_time;
    in[i].port_times = times[i];
  }
  const std::vector<SlaveTopology> topology = compute_topology(in);
  const std::vector<std::optional<std::uint32_t>> delays = compute_dc_delays(topology, times);
  for (std::size_t i = 0; i < slaves_.size(); ++i) slaves_[i].topology = topology[i];
  for (std::size_t i : dc) {
    SlaveInfo& s = slaves_[i];
    s.dc.delay_ns = delays[i].value_or(0);
    s.dc.offset_ns = master_time.count() - static_cast<std::int64_t>(s.dc.processing_unit_time);
    std::uint8_t off[8];
    store_le(off, static_cast<std::uint64_t>(s.dc.offset_ns));
    if (auto r = fpwr(s.station_address, reg::kDcSystemTimeOffset, off); !r) return fail(r.error());
    if (auto r = fpwr_u32(s.station_address, reg::kDcSystemTimeDelay, s.dc.delay_ns); !r) return fail(r.error());
  }
  dc_cyclic_ = true;
  return dc.size();
}

Expected<void, MasterError> Master::dc_static_drift_compensation(unsigned iterations, Command command) {
  if (!reference_clock_) return fail(MasterError::NotConfigured);
  if (command != Command::Frmw && command != Command::Armw) return fail(MasterError::InvalidArgument);
  const SlaveInfo& ref = slaves_[*reference_clock_];
  const std::uint16_t adp = command == Command::Frmw ? ref.station_address : auto_increment_adp(ref.position);
  for (unsigned i = 0; i < iterations; ++i) {
    std::fill(dc_time_.begin(), dc_time_.end(), 0);
    auto wkc = link_.exchange(command, device_address(adp, reg::kDcSystemTime), Bytes(dc_time_));
    if (!wkc) return fail(wkc.error());
    if (*wkc == 0) return fail(MasterError::WorkingCounter);
  }
  return {};
}

Expected<std::uint64_t, MasterError> Master::configure_sync0(std::size_t slave, std::uint32_t cycle_ns,
                                                             std::uint32_t shift_ns, Nanoseconds start_delay) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  if (cycle_ns == 0) return fail(MasterError::InvalidArgument);
  for (unsigned attempt = 0; attempt < kSync0StartAttempts; ++attempt) {
    auto start = program_sync0(slave, cycle_ns, shift_ns, start_delay);
    if (!start) return fail(start.error());
    auto running = sync0_started(slave);
    if (!running) return fail(running.error());
    if (*running) return *start;
  }
  return fail(MasterError::Sync0StartMissed);
}

Expected<std::uint64_t, MasterError> Master::program_sync0(std::size_t slave, std::uint32_t cycle_ns,
                                                           std::uint32_t shift_ns, Nanoseconds start_delay) {
  const std::uint16_t station = slaves_[slave].station_address;
  if (auto r = fpwr_u8(station, reg::kDcActivation, 0); !r) return fail(r.error());
  std::uint8_t now_b[8]{};
  if (auto r = fprd(station, reg::kDcSystemTime, now_b); !r) return fail(r.error());
  const std::uint64_t now = load_le<std::uint64_t>(now_b);
  const std::uint64_t first = now + static_cast<std::uint64_t>(start_delay.count());
  // Start on a whole cycle (SOEM ecx_dcsync0, ethercrab configure_dc_sync) plus the shift.
  const std::uint64_t start = (first / cycle_ns + 1) * cycle_ns + shift_ns;
  if (auto r = fpwr_u32(station, reg::kDcSync0CycleTime, cycle_ns); !r) return fail(r.error());
  std::uint8_t st[8];
  store_le(st, start);
  if (auto r = fpwr(station, reg::kDcStartTime, st); !r) return fail(r.error());
  if (auto r = fpwr_u8(station, reg::kDcActivation, reg::kDcActivateCyclic | reg::kDcActivateSync0); !r) {
    return fail(r.error());
  }
  return start;
}

// The system time first, then 0x0990, which reads the time of the next
// SYNC0 once the unit runs (ESC datasheet Section II 0x0990): a running unit's
// next pulse lies after the time read before it; a unit still waiting for
// its start time (in the future when 0x0981 was written) has it after too. A
// unit whose start time had passed by then waits for the wrap of the system
// time and reads that start time, now behind. Compared in the ESC's width (a
// 32-bit DC unit counts and compares the low 32 bits).
Expected<bool, MasterError> Master::sync0_started(std::size_t slave) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  const SlaveInfo& s = slaves_[slave];
  std::uint8_t now_b[8]{};
  if (auto r = fprd(s.station_address, reg::kDcSystemTime, now_b); !r) return fail(r.error());
  std::uint8_t next_b[8]{};
  if (auto r = fprd(s.station_address, reg::kDcStartTime, next_b); !r) return fail(r.error());
  const std::uint64_t ahead = load_le<std::uint64_t>(next_b) - load_le<std::uint64_t>(now_b);
  if ((s.esc.features & EscInfo::kFeatureDc64) == 0) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(ahead)) > 0;
  }
  return static_cast<std::int64_t>(ahead) > 0;
}

}  // namespace ecat::master
