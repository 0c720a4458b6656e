// N virtual CiA 402 drives (the built-in generic servo) in one slave::Chain,
// brought to Op with CSP enabled by a minimal master that speaks datagrams
// only: station addresses by APWR, identical SMs by BWR, per-slave FMMUs by
// FPWR, AL control by BWR, default PDO assignment (1600h -> SM2,
// 1A00h -> SM3). The process image is all outputs, then all inputs, in slave
// order (as SOEM lays it out). Then cycle() runs one 1 kHz CSP cycle: the
// LRW frames with every drive's process data (the first also carries ARMW
// 0910h for DC and BRD 0130h for AL status), and one Chain::poll - so every
// drive's firmware and application cycle runs as in ecat-slave's loop.
// Set-up allocates freely; cycle() does not allocate in this file.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "bench/bench_clock.hpp"
#include "bench/mini_master.hpp"
#include "coe/coe_header.hpp"
#include "coe/mailbox_header.hpp"
#include "coe/sdo_command.hpp"
#include "common/le.hpp"
#include "esc/dc/dc_registers.hpp"
#include "esi/device_loader.hpp"
#include "slave/chain.hpp"
#include "slave/fault_catalogue.hpp"  // DriveLine::cycle through a catalogue (bench_cycle)

namespace ecat::bench {

// CiA 402 (ETG.6010 / IEC 61800-7-201) values the cycle uses.
inline constexpr std::uint16_t kCwShutdown = 0x0006;
inline constexpr std::uint16_t kCwSwitchOn = 0x0007;
inline constexpr std::uint16_t kCwEnableOperation = 0x000F;
inline constexpr std::uint16_t kSwStateMask = 0x006F;
inline constexpr std::uint16_t kSwOperationEnabled = 0x0027;
inline constexpr std::uint8_t kModeCsp = 8;
// Offsets in the generic servo's fixed PDOs 1600h / 1A00h.
inline constexpr std::size_t kOutControlword = 0;
inline constexpr std::size_t kOutTargetPosition = 2;
inline constexpr std::size_t kOutMode = 12;
inline constexpr std::size_t kInStatusword = 0;
inline constexpr std::size_t kInActualPosition = 2;
inline constexpr std::size_t kInErrorCode = 14;

inline constexpr Nanoseconds kCyclePeriod{1'000'000};
// The set-point holds the position where the drive was enabled and is
// rewritten every cycle: the drive's position loop, plant simulation and
// monitoring all run each cycle (their cost does not depend on the motion),
// and no set-up of the user-unit scaling or limit switches is needed however
// long the benchmark runs.

class DriveLine {
 public:
  explicit DriveLine(std::size_t n) : DriveLine(n, default_device()) {}
  // N slaves of `dev`, one description shared by all (issue 16). A device
  // without a CiA 402 drive (an I/O slave) is taken to Op and cycled with
  // its process data as it is; a drive is also enabled in CSP.
  //
  // With `branch` > 0 the slaves form a tree instead (issue 30 item 2):
  // every branch-th slave is a junction on the previous junction's port 1,
  // the branch - 1 slaves after it hang in a line off its port 3; all with
  // four MII ports. The frame's order through the units is the slaves'
  // order, as on the line.
  DriveLine(std::size_t n, std::shared_ptr<const od::DeviceDescription> dev, std::size_t branch = 0)
      : chain_(clock_), n_(n) {
    for (const auto& p : dev->rx_pdos) if (p.sm == 2) out_ += p.bit_length() / 8;
    for (const auto& p : dev->tx_pdos) if (p.sm == 3) in_ += p.bit_length() / 8;
    if (branch > 0) {
      auto four = std::make_shared<od::DeviceDescription>(*dev);
      four->esc.physics = "YYYY";
      dev = std::move(four);  // may free the description passed in
    }
    // Taken after the swap above: a reference into the caller's description
    // would dangle once `dev` no longer owns it (the tree's SM0/SM1 were
    // written from freed memory, and PreOp refused with 0x0016).
    const auto& sms = dev->sync_managers;
    for (std::size_t i = 0; i < n; ++i) {
      slave::SlaveOptions o;
      o.name = "drive-" + std::to_string(i + 1);
      Expected<void, std::string> r;
      if (branch == 0 || i == 0) {
        r = chain_.add(dev, o);
      } else if (i % branch == 0) {
        r = chain_.attach(dev, o, i - branch, esc::kDownstreamPort);
      } else {
        r = chain_.attach(dev, o, i - 1, i % branch == 1 ? 3u : esc::kDownstreamPort);
      }
      if (!r) throw std::runtime_error(r.error());
    }
    // Station addresses, many APWRs per frame.
    batch([&](Frame& f, std::size_t i) {
      f.add(Command::Apwr,
            device_address(auto_increment_adp(static_cast<std::uint16_t>(i)), esc::reg::kConfiguredStationAddress),
            le16(station(i)));
    });
    broadcast_sm(0, sms.at(0).start_address, sms.at(0).default_size, sms.at(0).control);
    broadcast_sm(1, sms.at(1).start_address, sms.at(1).default_size, sms.at(1).control);
    request(od::EsmState::PreOp);
    broadcast_sm(2, sms.at(2).start_address, static_cast<std::uint16_t>(out_), sms.at(2).control);
    broadcast_sm(3, sms.at(3).start_address, static_cast<std::uint16_t>(in_), sms.at(3).control);
    batch([&](Frame& f, std::size_t i) {
      f.add(Command::Fpwr, device_address(station(i), esc::reg::fmmu(0)),
            fmmu_block(static_cast<std::uint32_t>(i * out_), static_cast<std::uint16_t>(out_),
                       sms[2].start_address, esc::fmmu_reg::kTypeWrite));
      f.add(Command::Fpwr, device_address(station(i), esc::reg::fmmu(1)),
            fmmu_block(static_cast<std::uint32_t>(n_ * out_ + i * in_), static_cast<std::uint16_t>(in_),
                       sms[3].start_address, esc::fmmu_reg::kTypeRead));
    });
    build_cycle_frames();
    request(od::EsmState::SafeOp);
    for (int i = 0; i < 3; ++i) cycle();
    request(od::EsmState::Op);
    if (!dev->drive) return;
    // Follow the actual position, set CSP, walk the power state machine.
    for (std::size_t d = 0; d < n_; ++d) {
      put_out(d, kOutMode, 1, kModeCsp);
      put_out(d, kOutTargetPosition, 4, static_cast<std::uint32_t>(actual_position(d)));
    }
    for (std::uint16_t cw : {kCwShutdown, kCwSwitchOn, kCwEnableOperation}) {
      for (std::size_t d = 0; d < n_; ++d) put_out(d, kOutControlword, 2, cw);
      for (int i = 0; i < 5; ++i) cycle();
    }
    for (std::size_t d = 0; d < n_; ++d) {
      if ((statusword(d) & kSwStateMask) != kSwOperationEnabled) {
        throw std::runtime_error("drive " + std::to_string(d) + " not enabled, statusword " +
                                 std::to_string(statusword(d)));
      }
      target_.push_back(actual_position(d));
    }
  }

  // One CSP cycle: new set-points, the frames, one poll of every slave.
  void cycle() noexcept { cycle(chain_); }
  // The same with the frames passed through `path` (anything with
  // Chain::process_frame's signature, e.g. slave::FaultCatalogue).
  template <typename FramePath>
  void cycle(FramePath& path) noexcept {
    now_ += kCyclePeriod;
    clock_.set(now_);
    for (std::size_t d = 0; d < target_.size(); ++d) {
      put_out(d, kOutTargetPosition, 4, static_cast<std::uint32_t>(target_[d]));
    }
    Nanoseconds t = now_;
    for (auto& f : frames_) {
      for (std::size_t k = 0; k < f->datagrams; ++k) f->frame.dg(k).set_wkc(0);
      (void)path.process_frame(f->frame.bytes(), t);
      t += kFrameSpacing;
    }
    (void)chain_.poll(t);
  }

  // DC Sync0 mode instead of free run, as a master configuring DC does
  // (ETG.1020 §5.2; shared/spec: SOEM's ecx_dcsync0, IgH's sync0 set-up):
  // back to PreOp, 1C32h:01 and 1C33h:01 = 2 by SDO download through each
  // slave's mailbox, the SYNC unit programmed from the device's DC OpMode
  // (0x09A0 the cycle, 0x0990 each slave's start from its own system time,
  // SYNC0 half a cycle after the cycle's frames; 0x0980/0x0981 =
  // AssignActivate), SafeOp, Op once SYNC0 runs, the drives enabled again.
  // Set-up only: anything refused throws. Not in the constructor: the
  // free-run cases' code stays as it is (bench_cycle; docs/performance-log.md
  // "Session 30", why bench_phases holds the other cases).
  // SM-synchronous mode instead of free run (1C32h:01 = 1, 1C33h:01 = 22h:
  // the application cycle on each SM2 event, inputs with it), as SOEM's
  // and IgH's masters run slaves without DC: back to PreOp, the modes by SDO
  // download, SafeOp, Op, the drives enabled again. Set-up only, as
  // to_dc_sync0.
  void to_sm_synchronous() {
    const od::DeviceDescription& dev = chain_[0].device();
    request(od::EsmState::PreOp);
    sdo_download_all(dev, kSmOutputParameter, kSyncModeSubindex, kSyncModeSmSynchronous, 1);
    sdo_download_all(dev, kSmInputParameter, kSyncModeSubindex, kSyncModeSynchronousWithSm2, 2);
    request(od::EsmState::SafeOp);
    request(od::EsmState::Op);
    enable_drives(true);
  }

  void to_dc_sync0() {
    const od::DeviceDescription& dev = chain_[0].device();
    const od::DcOpMode* dc = nullptr;
    for (const auto& m : dev.dc_op_modes) {
      if (m.assign_activate != 0) dc = &m;
    }
    if (dc == nullptr) throw std::runtime_error("the device has no DC OpMode");
    request(od::EsmState::PreOp);
    sdo_download_all(dev, kSmOutputParameter, kSyncModeSubindex, kSyncModeDcSync0, 1);
    sdo_download_all(dev, kSmInputParameter, kSyncModeSubindex, kSyncModeDcSync0, 2);
    // Each slave's system time against the simulated time of the frame
    // that read it, then its start time: the cycle after next, half a cycle in.
    std::vector<std::uint64_t> system(n_);
    per_slave_frames(kSystemTimeBytes, [&](Frame& f, std::size_t i) {
      return f.add(Command::Fprd, device_address(station(i), kSystemTime), kSystemTimeBytes);
    }, [&](const Frame& f, std::size_t i, std::size_t k) {
      system[i] = load_le<std::uint64_t>(f.dg(k).data().data()) - static_cast<std::uint64_t>(now_.count());
    });
    const std::uint64_t start_at = static_cast<std::uint64_t>((now_ + 2 * kCyclePeriod + kCyclePeriod / 2).count());
    per_slave_frames(kSystemTimeBytes, [&](Frame& f, std::size_t i) {
      Data t = le32(static_cast<std::uint32_t>(system[i] + start_at));
      for (auto b : le32(static_cast<std::uint32_t>((system[i] + start_at) >> 32))) t.push_back(b);
      return f.add(Command::Fpwr, device_address(station(i), kDcStartTime), t);
    }, nullptr);
    broadcast(kDcSync0Cycle, le32(static_cast<std::uint32_t>(kCyclePeriod.count() * dc->cycle_time_sync0_factor)));
    broadcast(kDcCyclicUnitControl, le16(dc->assign_activate));  // 0x0980, then 0x0981 (activation)
    request(od::EsmState::SafeOp);
    request(od::EsmState::Op);
    enable_drives(true);
  }

  std::size_t size() const noexcept { return n_; }
  // The simulated time of the last cycle's frames.
  Nanoseconds now() const noexcept { return now_; }
  std::size_t frames() const noexcept { return frames_.size(); }
  std::size_t image_bytes() const noexcept { return n_ * (out_ + in_); }
  std::uint16_t statusword(std::size_t d) const noexcept {
    return static_cast<std::uint16_t>(get_in(d, kInStatusword, 2));
  }
  std::int32_t actual_position(std::size_t d) const noexcept {
    return static_cast<std::int32_t>(get_in(d, kInActualPosition, 4));
  }
  std::uint16_t error_code(std::size_t d) const noexcept {
    return static_cast<std::uint16_t>(get_in(d, kInErrorCode, 2));
  }
  std::uint16_t al_status(std::size_t d) noexcept { return chain_[d].esc().register_u16(esc::reg::kAlStatus); }
  slave::Chain& chain() noexcept { return chain_; }
  BenchClock& clock() noexcept { return clock_; }
  // The built-in generic servo (esi::load_default_device).
  static std::shared_ptr<const od::DeviceDescription> default_device() {
    auto loaded = esi::load_default_device();
    if (!loaded) throw std::runtime_error(loaded.error().to_string());
    return std::make_shared<const od::DeviceDescription>(std::move(*loaded));
  }

 private:
  static constexpr Nanoseconds kFrameSpacing{10'000};
  static constexpr std::uint16_t kArmwBytes = 8;
  static constexpr std::uint16_t kAlStatusBytes = 2;
  static constexpr std::uint16_t kSystemTime = esc::reg::kDcBase + 0x10;  // 0x0910
  static constexpr int kMaxStatePolls = 200;

  struct CycleFrame {
    Frame frame;
    std::size_t datagrams = 0;
  };

  static Data fmmu_block(std::uint32_t logical, std::uint16_t length, std::uint16_t physical, std::uint8_t type) {
    Data d = le32(logical);
    for (auto b : le16(length)) d.push_back(b);
    d.push_back(0);
    d.push_back(7);
    for (auto b : le16(physical)) d.push_back(b);
    d.push_back(0);
    d.push_back(type);
    d.push_back(esc::fmmu_reg::kActivateEnable);
    d.resize(esc::reg::kFmmuStride, 0);
    return d;
  }

  void send(Frame& f) {
    now_ += kFrameSpacing;
    clock_.set(now_);
    if (!chain_.process_frame(f.finish(), now_)) throw std::runtime_error("set-up frame lost");
  }

  // Frames of per-slave datagrams, filled while they fit.
  template <typename Add>
  void batch(Add add) {
    constexpr std::size_t kRoom = 64;  // bytes the largest per-slave group needs
    auto f = std::make_unique<Frame>();
    for (std::size_t i = 0; i < n_; ++i) {
      if (f->remaining() < kRoom) {
        send(*f);
        f = std::make_unique<Frame>();
      }
      add(*f, i);
    }
    send(*f);
  }

  void broadcast_sm(unsigned sm, std::uint16_t start, std::uint16_t length, std::uint8_t control) {
    Frame f;
    f.add(Command::Bwr, device_address(0, esc::reg::sync_manager(sm)),
          Data{static_cast<std::uint8_t>(start), static_cast<std::uint8_t>(start >> 8),
               static_cast<std::uint8_t>(length), static_cast<std::uint8_t>(length >> 8), control, 0, kSmActivate, 0});
    send(f);
    if (f.wkc(0) != n_) throw std::runtime_error("SM" + std::to_string(sm) + " not taken by every slave");
  }

  static constexpr std::uint16_t kSmOutputParameter = 0x1C32;
  static constexpr std::uint16_t kSmInputParameter = 0x1C33;
  static constexpr std::uint8_t kSyncModeSubindex = 1;
  static constexpr std::uint16_t kSyncModeDcSync0 = 2;  // ETG.1020 1C32h:01
  static constexpr std::uint16_t kSyncModeSmSynchronous = 1;
  static constexpr std::uint16_t kSyncModeSynchronousWithSm2 = 0x22;  // 1C33h:01 only
  static constexpr std::uint16_t kSystemTimeBytes = 8;
  static constexpr std::uint16_t kDcStartTime = esc::reg::kDcBase + esc::dcreg::kStartTimeCyclicOperation;
  static constexpr std::uint16_t kDcSync0Cycle = esc::reg::kDcBase + esc::dcreg::kSync0CycleTime;
  static constexpr std::uint16_t kDcCyclicUnitControl = esc::reg::kDcBase + esc::dcreg::kCyclicUnitControl;
  static constexpr std::size_t kDatagramOverheadBytes = 12;
  static constexpr std::uint16_t kCwFaultReset = 0x0080;

  // One datagram per slave, as many slaves a frame as fit (each datagram
  // `bytes` long): `add` adds slave i's and returns its index in the frame,
  // `check` (may be null) reads it back once the frame came back.
  template <typename Add, typename Check>
  void per_slave_frames(std::size_t bytes, Add add, Check check) {
    std::size_t first = 0;
    while (first < n_) {
      Frame f;
      std::vector<std::size_t> at;
      std::size_t i = first;
      for (; i < n_ && f.remaining() >= bytes + kDatagramOverheadBytes; ++i) at.push_back(add(f, i));
      send(f);
      for (std::size_t k = 0; k < at.size(); ++k) {
        if (f.wkc(at[k]) != 1) throw std::runtime_error("slave " + std::to_string(first + k) + ": WKC " +
                                                        std::to_string(f.wkc(at[k])));
        if constexpr (!std::is_same_v<Check, std::nullptr_t>) check(f, first + k, at[k]);
      }
      first = i;
    }
  }

  void broadcast(std::uint16_t address, const Data& data) {
    Frame f;
    f.add(Command::Bwr, device_address(0, address), data);
    send(f);
    if (f.wkc(0) != n_) throw std::runtime_error("a BWR not taken by every slave");
  }

  // `value` into `index`:`sub` of every slave by an expedited SDO download
  // (mailbox counter `counter`): the whole SM0 written, then the whole SM1
  // read back, as SOEM and IgH do, and the answer checked.
  void sdo_download_all(const od::DeviceDescription& dev, std::uint16_t index, std::uint8_t sub,
                        std::uint16_t value, std::uint8_t counter) {
    const od::SyncManagerConfig& out = dev.sync_managers.at(0);
    const od::SyncManagerConfig& in = dev.sync_managers.at(1);
    // An expedited download of 2 bytes (ETG.1000.6 §5.6.2.1, CiA 301
    // §7.2.4.3.3), framed with the stack's own mailbox and CoE headers.
    constexpr std::size_t kValueBytes = sizeof(std::uint16_t);
    Data request(out.default_size, 0);
    coe::MailboxHeader header;
    header.length = static_cast<std::uint16_t>(coe::CoeHeader::kSize + coe::sdo::kHeaderSize);
    header.type = static_cast<std::uint8_t>(coe::MailboxType::CoE);
    header.counter = counter;
    header.pack(Bytes(request.data(), coe::MailboxHeader::kSize));
    ByteWriter w(Bytes(request.data() + coe::MailboxHeader::kSize, coe::CoeHeader::kSize + coe::sdo::kHeaderSize));
    coe::CoeHeader::write(w, coe::CoeService::SdoRequest);
    w.u8(coe::sdo::command(coe::sdo::kCcsInitiateDownload,
                           static_cast<std::uint8_t>(coe::sdo::kExpedited | coe::sdo::kSizeIndicated |
                                                     ((coe::sdo::kExpeditedMax - kValueBytes)
                                                      << coe::sdo::kUnusedShift))));
    w.u16(index);
    w.u8(sub);
    w.u32(value);
    // The answer: an initiate download response (scs 3) in the same place.
    constexpr std::size_t kCommandAt = coe::MailboxHeader::kSize + coe::CoeHeader::kSize;
    const std::uint8_t answered = coe::sdo::command(coe::sdo::kScsInitiateDownload);
    per_slave_frames(out.default_size, [&](Frame& f, std::size_t i) {
      return f.add(Command::Fpwr, device_address(station(i), out.start_address), request);
    }, nullptr);
    per_slave_frames(in.default_size, [&](Frame& f, std::size_t i) {
      return f.add(Command::Fprd, device_address(station(i), in.start_address), in.default_size);
    }, [&](const Frame& f, std::size_t i, std::size_t k) {
      const auto reply = f.dg(k).data();
      if (reply[kCommandAt] != answered) {
        throw std::runtime_error("slave " + std::to_string(i) + ": SDO download of " + std::to_string(index) +
                                 " answered with command " + std::to_string(reply[kCommandAt]));
      }
    });
  }

  // CSP, the set-point where each drive stands, the power state machine
  // walked to Operation enabled (from Fault first when `reset`). The
  // constructor walks the same sequence in its own lines on purpose:
  // calling this from it would change bench_cycle's code, which the
  // free-run cases compare between commits (bench_cycle.cpp.o stays
  // byte-identical; docs/performance-log.md "Session 30" and "Session 31").
  void enable_drives(bool reset) {
    target_.clear();
    for (std::size_t d = 0; d < n_; ++d) {
      put_out(d, kOutMode, 1, kModeCsp);
      put_out(d, kOutTargetPosition, 4, static_cast<std::uint32_t>(actual_position(d)));
    }
    const std::uint16_t none = 0;
    for (std::uint16_t cw : {reset ? kCwFaultReset : none, none, kCwShutdown, kCwSwitchOn, kCwEnableOperation}) {
      if (cw == none && !reset) continue;
      for (std::size_t d = 0; d < n_; ++d) put_out(d, kOutControlword, 2, cw);
      for (int i = 0; i < 5; ++i) cycle();
    }
    for (std::size_t d = 0; d < n_; ++d) {
      if ((statusword(d) & kSwStateMask) != kSwOperationEnabled) {
        throw std::runtime_error("drive " + std::to_string(d) + " not enabled, statusword " +
                                 std::to_string(statusword(d)));
      }
      target_.push_back(actual_position(d));
    }
  }

  void request(od::EsmState state) {
    const auto want = static_cast<std::uint8_t>(state);
    Frame f;
    f.add(Command::Bwr, device_address(0, esc::reg::kAlControl), le16(want));
    send(f);
    for (int i = 0; i < kMaxStatePolls; ++i) {
      if (!frames_.empty()) {
        cycle();
      } else {
        now_ += kCyclePeriod;
        clock_.set(now_);
        (void)chain_.poll(now_);
      }
      bool all = true;
      for (std::size_t s = 0; s < n_ && all; ++s) {
        all = (chain_[s].esc().register_u16(esc::reg::kAlStatus) & 0x0F) == want;
      }
      if (all) return;
    }
    const std::uint16_t st = chain_[0].esc().register_u16(esc::reg::kAlStatus);
    const std::uint16_t code = chain_[0].esc().register_u16(esc::reg::kAlStatusCode);
    throw std::runtime_error("state " + std::to_string(want) + " not reached: AL status " + std::to_string(st) +
                             " code " + std::to_string(code));
  }

  void build_cycle_frames() {
    const std::size_t total = image_bytes();
    std::size_t at = 0;
    byte_.assign(total, nullptr);
    while (at < total || frames_.empty()) {
      auto cf = std::make_unique<CycleFrame>();
      if (frames_.empty()) {
        cf->frame.add(Command::Armw, device_address(auto_increment_adp(0), kSystemTime), kArmwBytes);
        cf->frame.add(Command::Brd, device_address(0, esc::reg::kAlStatus), kAlStatusBytes);
        cf->datagrams = 2;
      }
      const auto len = static_cast<std::uint16_t>(std::min(total - at, cf->frame.remaining()));
      const std::size_t k = cf->frame.add(Command::Lrw, static_cast<std::uint32_t>(at), len);
      ++cf->datagrams;
      cf->frame.finish();
      auto data = cf->frame.dg(k).data();
      for (std::size_t i = 0; i < len; ++i) byte_[at + i] = data.data() + i;
      at += len;
      frames_.push_back(std::move(cf));
    }
  }

  void put_out(std::size_t d, std::size_t offset, std::size_t bytes, std::uint32_t v) noexcept {
    for (std::size_t i = 0; i < bytes; ++i) *byte_[d * out_ + offset + i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
  std::uint32_t get_in(std::size_t d, std::size_t offset, std::size_t bytes) const noexcept {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < bytes; ++i) v |= static_cast<std::uint32_t>(*byte_[n_ * out_ + d * in_ + offset + i]) << (8 * i);
    return v;
  }

  BenchClock clock_;
  slave::Chain chain_;
  std::size_t n_;
  std::size_t out_ = 0;
  std::size_t in_ = 0;
  Nanoseconds now_{0};
  std::vector<std::unique_ptr<CycleFrame>> frames_;
  std::vector<std::uint8_t*> byte_;  // logical image byte -> its place in a cycle frame
  std::vector<std::int32_t> target_;  // where each drive was enabled
};

}  // namespace ecat::bench
