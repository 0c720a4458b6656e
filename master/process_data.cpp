// Process data: SM + FMMU set-up from the PDO sizes (SM2/SM3, or every
// process-data SM where a device has several per direction) and the cyclic LRW
// (masters.md §1.3/§1.4, esc-registers.md §6/§7). Layout as SOEM: all
// outputs in slave order, then all inputs; expected WKC = 2 per slave with
// outputs + 1 per slave with inputs (ETG.1000.4 §5.4.3 LRW counting).
#include <algorithm>
#include <cstring>

#include "common/frame.hpp"
#include "master/master.hpp"
#include "master/registers.hpp"

namespace ecat::master {

namespace {
constexpr std::uint8_t kOutputsControl = 0x64;  // 3-buffer, write, watchdog trigger
constexpr std::uint8_t kInputsControl = 0x20;   // 3-buffer, read
constexpr std::uint8_t kFmmuStopBit = 7;
constexpr unsigned kOutputSm = 2;
constexpr unsigned kInputSm = 3;
constexpr std::uint32_t kBitsPerByte = 8;

// FMMU register block (esc-registers.md §6).
std::array<std::uint8_t, reg::kFmmuSize> fmmu_block(std::uint32_t logical, std::uint16_t length,
                                                    std::uint16_t physical, std::uint8_t type) {
  std::array<std::uint8_t, reg::kFmmuSize> b{};
  ByteWriter w(b);
  w.u32(logical);
  w.u16(length);
  w.u8(0);             // logical start bit
  w.u8(kFmmuStopBit);  // logical stop bit
  w.u16(physical);
  w.u8(0);  // physical start bit
  w.u8(type);
  w.u8(length > 0 ? 1 : 0);  // activate
  return b;
}

}  // namespace

Expected<void, MasterError> Master::write_sync_manager(std::size_t slave, unsigned n, std::uint16_t start,
                                                       std::uint16_t length, std::uint8_t control, bool enable) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  const std::uint16_t station = slaves_[slave].station_address;
  const std::array<std::uint8_t, reg::kSyncManagerSize> off{};
  if (auto r = fpwr(station, reg::sync_manager(n), off); !r) return fail(r.error());
  std::array<std::uint8_t, reg::kSyncManagerSize> b{};
  ByteWriter w(b);
  w.u16(start);
  w.u16(length);
  w.u8(control);
  w.u8(0);
  w.u8(enable ? reg::kSmActivateEnable : 0);
  w.u8(0);
  return fpwr(station, reg::sync_manager(n), b);
}

namespace {

// The SMs a slave's process data goes through: those sized per SM, or SM2
// (outputs) and SM3 (inputs) with start/control from the SII SYNCM category
// when it has them.
void legacy_sms(SlaveInfo& s) {
  const auto& sms = s.sii.sync_managers;
  if (sms.size() > kOutputSm && sms[kOutputSm].start != 0) {
    s.pd.sm2_start = sms[kOutputSm].start;
    s.pd.sm2_control = sms[kOutputSm].control;
  } else if (s.pd.sm2_start == 0) {
    s.pd.sm2_control = kOutputsControl;
  }
  if (sms.size() > kInputSm && sms[kInputSm].start != 0) {
    s.pd.sm3_start = sms[kInputSm].start;
    s.pd.sm3_control = sms[kInputSm].control;
  } else if (s.pd.sm3_start == 0) {
    s.pd.sm3_control = kInputsControl;
  }
  s.pd.sms = {ProcessSm{kOutputSm, true, s.pd.sm2_start, s.pd.sm2_control, s.pd.output_bytes, 0},
              ProcessSm{kInputSm, false, s.pd.sm3_start, s.pd.sm3_control, s.pd.input_bytes, 0}};
}

}  // namespace

void Master::size_process_data_from_sii(std::size_t slave) {
  SlaveInfo& s = slaves_[slave];
  s.pd.sms.clear();
  const auto& sms = s.sii.sync_managers;
  for (std::size_t n = 0; n < sms.size(); ++n) {
    const bool outputs = sms[n].type == sii::kSmTypeOutputs;
    if (!outputs && sms[n].type != sii::kSmTypeInputs) continue;
    const std::uint32_t bits = s.sii.default_pdo_bits(!outputs, static_cast<std::uint8_t>(n));
    s.pd.sms.push_back(ProcessSm{static_cast<std::uint8_t>(n), outputs, sms[n].start, sms[n].control,
                                 static_cast<std::uint16_t>((bits + kBitsPerByte - 1) / kBitsPerByte), 0});
  }
  s.pd.per_sm = !s.pd.sms.empty();
  if (s.pd.per_sm) {
    s.pd.sum_sizes();
  } else {  // no SYNCM category: the SII PDOs of SM2/SM3
    s.pd.output_bytes = static_cast<std::uint16_t>((s.sii.default_pdo_bits(false, kOutputSm) + kBitsPerByte - 1) / kBitsPerByte);
    s.pd.input_bytes = static_cast<std::uint16_t>((s.sii.default_pdo_bits(true, kInputSm) + kBitsPerByte - 1) / kBitsPerByte);
  }
}

Expected<void, MasterError> Master::configure_process_data() {
  output_bytes_ = 0;
  input_bytes_ = 0;
  expected_wkc_ = 0;
  for (auto& s : slaves_) {
    if (s.pd.per_sm) {
      s.pd.sum_sizes();
    } else {
      legacy_sms(s);
    }
  }
  // Each slave's outputs SMs side by side in SM order, then (after all
  // slaves' outputs) its inputs SMs (SOEM's layout, masters.md §1.3 step 4).
  for (auto& s : slaves_) {
    s.pd.output_offset = output_bytes_;
    for (ProcessSm& p : s.pd.sms) {
      if (!p.outputs) continue;
      p.logical = output_bytes_;
      output_bytes_ += p.bytes;
    }
  }
  for (auto& s : slaves_) {
    s.pd.input_offset = output_bytes_ + input_bytes_;
    for (ProcessSm& p : s.pd.sms) {
      if (p.outputs) continue;
      p.logical = output_bytes_ + input_bytes_;
      input_bytes_ += p.bytes;
    }
  }
  // Then one status byte per mailbox slave (SOEM's layout), read like inputs.
  for (auto& s : slaves_) {
    s.pd.mailbox_status_offset.reset();
    if (config_.map_mailbox_status && s.mailbox.configured) {
      s.pd.mailbox_status_offset = output_bytes_ + input_bytes_;
      ++input_bytes_;
    }
  }
  if (output_bytes_ + input_bytes_ > kMaxDatagramData) return fail(MasterError::InvalidArgument);
  image_.assign(output_bytes_ + input_bytes_, 0);
  use_lrw_ = true;
  for (const auto& s : slaves_) {
    const bool not_lrw = (s.esc.features & EscInfo::kFeatureNoLrw) != 0 ||
                         (s.sii.general && (s.sii.general->flags & sii::kFlagNotLrw) != 0);
    if (not_lrw) use_lrw_ = false;
  }

  for (std::size_t i = 0; i < slaves_.size(); ++i) {
    SlaveInfo& s = slaves_[i];
    // Every process-data SM, enabled iff length > 0 (SOEM, IgH).
    for (const ProcessSm& p : s.pd.sms) {
      if (auto r = write_sync_manager(i, p.sm, p.start, p.bytes, p.control, p.bytes > 0); !r) return fail(r.error());
    }
    // One FMMU per run of SMs of a direction that lie back to back in the
    // ESC (EK1828's SM0 at 0F00h and SM1 at 0F01h: one 2-byte FMMU, as SOEM
    // joins them) - the logical side is back to back by construction.
    unsigned next_fmmu = 0;
    bool any_outputs = false;
    for (const bool outputs : {true, false}) {
      const ProcessSm* run = nullptr;
      std::uint32_t run_bytes = 0;
      auto flush = [&]() -> Expected<void, MasterError> {
        if (run == nullptr || run_bytes == 0) return {};
        if (s.esc.fmmus != 0 && next_fmmu >= s.esc.fmmus) return fail(MasterError::InvalidArgument);
        const auto b = fmmu_block(run->logical, static_cast<std::uint16_t>(run_bytes), run->start,
                                  outputs ? reg::kFmmuWrite : reg::kFmmuRead);
        return fpwr(s.station_address, reg::fmmu(next_fmmu++), b);
      };
      for (const ProcessSm& p : s.pd.sms) {
        if (p.outputs != outputs || p.bytes == 0) continue;
        if (outputs) any_outputs = true;
        if (run != nullptr && run->start + run_bytes == p.start && run->logical + run_bytes == p.logical) {
          run_bytes += p.bytes;
          continue;
        }
        if (auto r = flush(); !r) return fail(r.error());
        run = &p;
        run_bytes = p.bytes;
      }
      if (auto r = flush(); !r) return fail(r.error());
    }
    if (any_outputs) expected_wkc_ = static_cast<std::uint16_t>(expected_wkc_ + 2);
    if (s.pd.mailbox_status_offset) {
      const auto status = static_cast<std::uint16_t>(reg::sync_manager(1) + reg::kSmStatusOffset);
      const auto b = fmmu_block(*s.pd.mailbox_status_offset, 1, status, reg::kFmmuRead);
      if (auto r = fpwr(s.station_address, reg::fmmu(next_fmmu++), b); !r) return fail(r.error());
    }
    // One read count per slave however many read FMMUs it has (ETG.1000.4 §5.4.3).
    if (s.pd.input_bytes > 0 || s.pd.mailbox_status_offset) expected_wkc_ = static_cast<std::uint16_t>(expected_wkc_ + 1);
    s.pd.configured = true;
  }
  pd_configured_ = true;
  return {};
}

bool Master::mailbox_reply_flagged(std::size_t slave) const noexcept {
  if (slave >= slaves_.size() || image_.empty()) return false;
  const auto& at = slaves_[slave].pd.mailbox_status_offset;
  return at && *at < image_.size() && (image_[*at] & reg::kSmStatusMailboxFull) != 0;
}

Bytes Master::outputs(std::size_t slave) {
  if (slave >= slaves_.size() || image_.empty()) return {};
  const auto& pd = slaves_[slave].pd;
  return Bytes(image_.data() + pd.output_offset, pd.output_bytes);
}

ConstBytes Master::inputs(std::size_t slave) const {
  if (slave >= slaves_.size() || image_.empty()) return {};
  const auto& pd = slaves_[slave].pd;
  return ConstBytes(image_.data() + pd.input_offset, pd.input_bytes);
}

Expected<CyclicResult, MasterError> Master::exchange_process_data() {
  if (!pd_configured_) return fail(MasterError::NotConfigured);
  // A segment without process data (couplers, mailbox-only devices) still
  // gets a cyclic frame: a BRD of the AL status, answered by every slave
  // (WKC = slave count), as TwinCAT's cyclic frame checks the states.
  const bool state_only = image_.empty();
  // The LRW carries the outputs and gets the inputs back; keep the outputs
  // region of the image intact (the reply data of output bytes equals them).
  std::array<Datagram, 3> dgs{};
  std::size_t n = 0;
  if (dc_cyclic_ && reference_clock_) {
    std::fill(dc_time_.begin(), dc_time_.end(), 0);
    dgs[n++] = Datagram{Command::Frmw, device_address(slaves_[*reference_clock_].station_address, reg::kDcSystemTime),
                        Bytes(dc_time_), 0};
  }
  const std::size_t first = n;
  if (state_only) {
    dgs[n++] = Datagram{Command::Brd, device_address(0, reg::kAlStatus), Bytes(al_status_), 0};
  } else if (use_lrw_) {
    dgs[n++] = Datagram{Command::Lrw, 0, Bytes(image_), 0};
  } else {
    if (output_bytes_ > 0) dgs[n++] = Datagram{Command::Lwr, 0, Bytes(image_.data(), output_bytes_), 0};
    if (input_bytes_ > 0) {
      dgs[n++] = Datagram{Command::Lrd, output_bytes_, Bytes(image_.data() + output_bytes_, input_bytes_), 0};
    }
  }
  const Nanoseconds start = clock_.now();
  auto r = link_.exchange(std::span<Datagram>(dgs.data(), n));
  ++cyclic_stats_.cycles;
  if (!r) {
    ++cyclic_stats_.lost_frames;
    return fail(r.error());
  }
  CyclicResult res;
  res.sent_at = start;
  // FRMW: the reference reads (WKC +1), every other DC slave writes (+1 each).
  if (first == 1 && dgs[0].wkc >= 1) res.reference_time = load_le<std::uint64_t>(dc_time_.data());
  for (std::size_t i = first; i < n; ++i) {
    res.wkc = static_cast<std::uint16_t>(res.wkc + (dgs[i].command == Command::Lwr ? 2 * dgs[i].wkc : dgs[i].wkc));
  }
  res.expected_wkc = state_only ? static_cast<std::uint16_t>(slaves_.size()) : expected_wkc_;
  res.round_trip = clock_.now() - start;
  if (!res.ok()) ++cyclic_stats_.wkc_errors;
  if (cyclic_stats_.cycles == 1 || res.round_trip < cyclic_stats_.min_round_trip) {
    cyclic_stats_.min_round_trip = res.round_trip;
  }
  cyclic_stats_.max_round_trip = std::max(cyclic_stats_.max_round_trip, res.round_trip);
  cyclic_stats_.total_round_trip += res.round_trip;
  return res;
}

}  // namespace ecat::master
