// Process data: SM + FMMU set-up from the PDO sizes (SM2/SM3, or every
// process-data SM where a device has several per direction) and the cyclic LRW
// (masters.md §1.3/§1.4, esc-registers.md §6/§7). Layout as SOEM: all
// outputs in slave order, then all inputs; expected WKC = 2 per slave with
// outputs + 1 per slave with inputs (ETG.1000.4 §5.4.3 LRW counting), per
// datagram when the image needs several (master/process_image_plan.hpp).
#include <algorithm>
#include <array>
#include <optional>
#include <cstring>

#include "common/frame.hpp"
#include "master/datagram_batch.hpp"
#include "master/master.hpp"
#include "master/process_image_plan.hpp"
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

std::array<std::uint8_t, reg::kSyncManagerSize> sync_manager_block(std::uint16_t start, std::uint16_t length,
                                                                   std::uint8_t control, bool enable) {
  std::array<std::uint8_t, reg::kSyncManagerSize> b{};
  ByteWriter w(b);
  w.u16(start);
  w.u16(length);
  w.u8(control);
  w.u8(0);
  w.u8(enable ? reg::kSmActivateEnable : 0);
  w.u8(0);
  return b;
}

}  // namespace

Expected<void, MasterError> Master::write_sync_manager(std::size_t slave, unsigned n, std::uint16_t start,
                                                       std::uint16_t length, std::uint8_t control, bool enable) {
  if (auto c = check_slave(slave); !c) return fail(c.error());
  const std::uint16_t station = slaves_[slave].station_address;
  const std::array<std::uint8_t, reg::kSyncManagerSize> off{};
  if (auto r = fpwr(station, reg::sync_manager(n), off); !r) return fail(r.error());
  return fpwr(station, reg::sync_manager(n), sync_manager_block(start, length, control, enable));
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

// The process-data SMs and FMMUs of one slave, as datagrams added to
// `batch`; false when the slave has too few FMMUs.
bool Master::add_process_data_config(DatagramBatch& batch, const SlaveInfo& s) {
  static constexpr std::array<std::uint8_t, reg::kSyncManagerSize> kOff{};
  const auto station = s.station_address;
  // Each SM first off (start/length/control are writable only while it is
  // off, Section II 0x0800), then enabled iff length > 0 (SOEM, IgH).
  for (const ProcessSm& p : s.pd.sms) {
    batch.add(Command::Fpwr, device_address(station, reg::sync_manager(p.sm)), kOff);
    batch.add(Command::Fpwr, device_address(station, reg::sync_manager(p.sm)),
              sync_manager_block(p.start, p.bytes, p.control, p.bytes > 0));
  }
  // One FMMU per run of SMs of a direction that lie back to back in the
  // ESC (EK1828's SM0 at 0F00h and SM1 at 0F01h: one 2-byte FMMU, as SOEM
  // joins them) - the logical side is back to back by construction.
  unsigned next_fmmu = 0;
  for (const bool outputs : {true, false}) {
    const ProcessSm* run = nullptr;
    std::uint32_t run_bytes = 0;
    auto flush = [&]() -> bool {
      if (run == nullptr || run_bytes == 0) return true;
      if (s.esc.fmmus != 0 && next_fmmu >= s.esc.fmmus) return false;
      batch.add(Command::Fpwr, device_address(station, reg::fmmu(next_fmmu++)),
                fmmu_block(run->logical, static_cast<std::uint16_t>(run_bytes), run->start,
                           outputs ? reg::kFmmuWrite : reg::kFmmuRead));
      return true;
    };
    for (const ProcessSm& p : s.pd.sms) {
      if (p.outputs != outputs || p.bytes == 0) continue;
      if (run != nullptr && run->start + run_bytes == p.start && run->logical + run_bytes == p.logical) {
        run_bytes += p.bytes;
        continue;
      }
      if (!flush()) return false;
      run = &p;
      run_bytes = p.bytes;
    }
    if (!flush()) return false;
  }
  if (s.pd.mailbox_status_offset) {
    const auto status = static_cast<std::uint16_t>(reg::sync_manager(1) + reg::kSmStatusOffset);
    batch.add(Command::Fpwr, device_address(station, reg::fmmu(next_fmmu++)),
              fmmu_block(*s.pd.mailbox_status_offset, 1, status, reg::kFmmuRead));
  }
  return true;
}

Expected<void, MasterError> Master::configure_process_data() {
  pd_configured_ = false;
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
  use_lrw_ = true;
  for (const auto& s : slaves_) {
    const bool not_lrw = (s.esc.features & EscInfo::kFeatureNoLrw) != 0 ||
                         (s.sii.general && (s.sii.general->flags & sii::kFlagNotLrw) != 0);
    if (not_lrw) use_lrw_ = false;
  }
  // The FMMU windows in logical order: outputs, inputs, status bytes. A
  // slave's SMs of one direction are back to back in the image, so one span
  // per slave and direction (its WKC counts once per datagram however many
  // FMMUs it has, ETG.1000.4 §5.4.3).
  std::vector<FmmuSpan> spans;
  for (std::uint32_t i = 0; i < slaves_.size(); ++i) {
    const auto& pd = slaves_[i].pd;
    if (pd.output_bytes > 0) spans.push_back(FmmuSpan{pd.output_offset, pd.output_bytes, i, true});
  }
  for (std::uint32_t i = 0; i < slaves_.size(); ++i) {
    const auto& pd = slaves_[i].pd;
    if (pd.input_bytes > 0) spans.push_back(FmmuSpan{pd.input_offset, pd.input_bytes, i, false});
  }
  for (std::uint32_t i = 0; i < slaves_.size(); ++i) {
    const auto& at = slaves_[i].pd.mailbox_status_offset;
    if (at) spans.push_back(FmmuSpan{*at, 1, i, false});
  }
  PlanLimits limits;
  limits.max_datagram_data = config_.max_process_datagram;
  // SOEM keeps room for the DC reference's FRMW in the first frame (EC_FIRSTDCDATAGRAM).
  limits.first_frame_reserved = reference_clock_ ? kDcDatagramBytes : 0;
  auto plan = plan_process_image(spans, output_bytes_, output_bytes_ + input_bytes_, use_lrw_, limits);
  if (!plan) return fail(plan.error());
  image_.assign(output_bytes_ + input_bytes_, 0);

  // The process-data SMs and the FMMUs of every slave, packed into as few
  // frames as fit.
  DatagramBatch batch;
  for (const SlaveInfo& s : slaves_) {
    if (!add_process_data_config(batch, s)) return fail(MasterError::InvalidArgument);
  }
  if (auto r = batch.exchange(link_); !r) return fail(r.error());
  if (!batch.all_wkc(1)) return fail(MasterError::WorkingCounter);
  for (auto& s : slaves_) s.pd.configured = true;

  // The cyclic datagrams: [FRMW 0x0910 to the DC reference, frame 0 only] +
  // the plan's logical datagrams over the image, grouped per frame.
  pd_plan_ = std::move(plan->datagrams);
  pd_frames_ = plan->frames;
  pd_datagrams_.clear();
  pd_frame_begin_.clear();
  pd_datagrams_.push_back(Datagram{Command::Frmw, 0, Bytes(dc_time_), 0});
  for (const PdDatagram& d : pd_plan_) {
    if (pd_frame_begin_.size() == d.frame) pd_frame_begin_.push_back(pd_datagrams_.size());
    pd_datagrams_.push_back(Datagram{d.command, d.logical, Bytes(image_.data() + d.logical, d.length), 0});
    // Totals count an LWR twice so that they equal the LRW ones (SOEM).
    expected_wkc_ = static_cast<std::uint16_t>(expected_wkc_ + (d.command == Command::Lwr ? 2 : 1) * d.expected_wkc);
  }
  pd_frame_begin_.push_back(pd_datagrams_.size());
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
  CyclicResult res;
  const Nanoseconds start = clock_.now();
  res.sent_at = start;
  ++cyclic_stats_.cycles;
  const bool dc = dc_cyclic_ && reference_clock_;
  if (image_.empty()) {
    // A segment without process data (couplers, mailbox-only devices) still
    // gets a cyclic frame: a BRD of the AL status, answered by every slave
    // (WKC = slave count), as TwinCAT's cyclic frame checks the states.
    std::array<Datagram, 2> dgs{};
    std::size_t n = 0;
    if (dc) {
      std::fill(dc_time_.begin(), dc_time_.end(), 0);
      dgs[n++] = Datagram{Command::Frmw,
                          device_address(slaves_[*reference_clock_].station_address, reg::kDcSystemTime),
                          Bytes(dc_time_), 0};
    }
    dgs[n++] = Datagram{Command::Brd, device_address(0, reg::kAlStatus), Bytes(al_status_), 0};
    auto r = link_.exchange(std::span<Datagram>(dgs.data(), n));
    if (!r) {
      ++cyclic_stats_.lost_frames;
      return fail(r.error());
    }
    if (dc && dgs[0].wkc >= 1) res.reference_time = load_le<std::uint64_t>(dc_time_.data());
    res.wkc = dgs[n - 1].wkc;
    res.expected_wkc = static_cast<std::uint16_t>(slaves_.size());
    res.frames = 1;
  } else {
    // The frames one after the other; the outputs region of the image stays
    // intact (the reply data of output bytes equals them). A lost frame does
    // not stop the others: the cycle still delivers what came back.
    std::optional<MasterError> lost;
    if (dc) {
      std::fill(dc_time_.begin(), dc_time_.end(), 0);
      pd_datagrams_[0].address = device_address(slaves_[*reference_clock_].station_address, reg::kDcSystemTime);
      pd_datagrams_[0].data = Bytes(dc_time_);
      pd_datagrams_[0].wkc = 0;
    }
    for (std::size_t f = 0; f < pd_frames_; ++f) {
      const std::size_t begin = (f == 0 && dc) ? 0 : pd_frame_begin_[f];
      const std::span<Datagram> frame(pd_datagrams_.data() + begin, pd_frame_begin_[f + 1] - begin);
      for (Datagram& d : frame) d.wkc = 0;
      if (auto r = link_.exchange(frame); !r) {
        ++cyclic_stats_.lost_frames;
        lost = r.error();
      }
    }
    if (dc && pd_datagrams_[0].wkc >= 1) res.reference_time = load_le<std::uint64_t>(dc_time_.data());
    for (std::size_t i = 0; i < pd_plan_.size(); ++i) {
      const Datagram& d = pd_datagrams_[i + 1];
      res.wkc = static_cast<std::uint16_t>(res.wkc + (d.command == Command::Lwr ? 2 * d.wkc : d.wkc));
      if (d.wkc != pd_plan_[i].expected_wkc) ++res.datagrams_wrong;
    }
    res.expected_wkc = expected_wkc_;
    res.frames = static_cast<std::uint16_t>(pd_frames_);
    if (lost) return fail(*lost);
  }
  res.round_trip = clock_.now() - start;
  if (!res.ok()) ++cyclic_stats_.wkc_errors;
  if (cyclic_stats_.cycles == 1 || res.round_trip < cyclic_stats_.min_round_trip) {
    cyclic_stats_.min_round_trip = res.round_trip;
  }
  cyclic_stats_.max_round_trip = std::max(cyclic_stats_.max_round_trip, res.round_trip);
  cyclic_stats_.total_round_trip += res.round_trip;
  return res;
}

std::uint16_t Master::last_datagram_wkc(std::size_t i) const noexcept {
  return i < pd_plan_.size() ? pd_datagrams_[i + 1].wkc : 0;
}

}  // namespace ecat::master
