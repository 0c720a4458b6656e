// Register access and the bus scan (masters.md §1.1, §2.1, §4.1).
#include "master/master.hpp"

#include <array>

#include "common/frame.hpp"
#include "master/datagram_batch.hpp"
#include "master/registers.hpp"

namespace ecat::master {

std::string_view describe(AlState s) noexcept {
  switch (s) {
    case AlState::Init: return "Init";
    case AlState::PreOp: return "PreOp";
    case AlState::Boot: return "Boot";
    case AlState::SafeOp: return "SafeOp";
    case AlState::Op: return "Op";
  }
  return "?";
}

Master::Master(transport::Transport& transport, const Clock& clock, MasterConfig config)
    : transport_(transport), clock_(clock), config_(config), link_(transport, clock, config.link) {}

Expected<std::uint16_t, MasterError> Master::transact(Command command, std::uint32_t address, Bytes data) {
  return link_.exchange(command, address, data);
}

Expected<void, MasterError> Master::fprd(std::uint16_t station, std::uint16_t reg, Bytes out) {
  auto wkc = link_.exchange(Command::Fprd, device_address(station, reg), out);
  if (!wkc) return fail(wkc.error());
  if (*wkc != 1) return fail(MasterError::WorkingCounter);
  return {};
}

Expected<void, MasterError> Master::fpwr(std::uint16_t station, std::uint16_t reg, ConstBytes in) {
  std::array<std::uint8_t, kMaxDatagramData> buf;
  if (in.size() > buf.size()) return fail(MasterError::InvalidArgument);
  std::copy(in.begin(), in.end(), buf.begin());
  auto wkc = link_.exchange(Command::Fpwr, device_address(station, reg), Bytes(buf.data(), in.size()));
  if (!wkc) return fail(wkc.error());
  if (*wkc != 1) return fail(MasterError::WorkingCounter);
  return {};
}

Expected<std::uint8_t, MasterError> Master::fprd_u8(std::uint16_t station, std::uint16_t reg) {
  std::uint8_t b[1]{};
  if (auto r = fprd(station, reg, b); !r) return fail(r.error());
  return b[0];
}

Expected<std::uint16_t, MasterError> Master::fprd_u16(std::uint16_t station, std::uint16_t reg) {
  std::uint8_t b[2]{};
  if (auto r = fprd(station, reg, b); !r) return fail(r.error());
  return load_le<std::uint16_t>(b);
}

Expected<std::uint32_t, MasterError> Master::fprd_u32(std::uint16_t station, std::uint16_t reg) {
  std::uint8_t b[4]{};
  if (auto r = fprd(station, reg, b); !r) return fail(r.error());
  return load_le<std::uint32_t>(b);
}

Expected<void, MasterError> Master::fpwr_u8(std::uint16_t station, std::uint16_t reg, std::uint8_t v) {
  const std::uint8_t b[1]{v};
  return fpwr(station, reg, b);
}

Expected<void, MasterError> Master::fpwr_u16(std::uint16_t station, std::uint16_t reg, std::uint16_t v) {
  std::uint8_t b[2];
  store_le(b, v);
  return fpwr(station, reg, b);
}

Expected<void, MasterError> Master::fpwr_u32(std::uint16_t station, std::uint16_t reg, std::uint32_t v) {
  std::uint8_t b[4];
  store_le(b, v);
  return fpwr(station, reg, b);
}

Expected<std::uint16_t, MasterError> Master::bwr(std::uint16_t reg, ConstBytes in) {
  std::array<std::uint8_t, kMaxDatagramData> buf;
  if (in.size() > buf.size()) return fail(MasterError::InvalidArgument);
  std::copy(in.begin(), in.end(), buf.begin());
  return link_.exchange(Command::Bwr, device_address(0, reg), Bytes(buf.data(), in.size()));
}

Expected<void, MasterError> Master::check_slave(std::size_t slave) const {
  if (slave >= slaves_.size()) return fail(MasterError::InvalidArgument);
  return {};
}

Expected<std::size_t, MasterError> Master::count_slaves() {
  std::uint8_t data[2]{};
  auto wkc = link_.exchange(Command::Brd, device_address(0, reg::kType), data);
  if (!wkc) return fail(wkc.error());
  return static_cast<std::size_t>(*wkc);
}

Expected<void, MasterError> Master::clear_write_protection() {
  std::uint8_t enable_registers[1]{reg::kWriteEnableBit};
  std::uint8_t enable_esc[1]{reg::kWriteEnableBit};
  std::uint8_t unprotect_registers[1]{0};
  std::uint8_t unprotect_esc[1]{0};
  std::array<Datagram, 4> frame{{
      {Command::Bwr, device_address(0, reg::kRegisterWriteEnable), enable_registers},
      {Command::Bwr, device_address(0, reg::kEscWriteEnable), enable_esc},
      {Command::Bwr, device_address(0, reg::kRegisterWriteProtection), unprotect_registers},
      {Command::Bwr, device_address(0, reg::kEscWriteProtection), unprotect_esc},
  }};
  return link_.exchange(frame);
}

Expected<std::size_t, MasterError> Master::scan() {
  slaves_.clear();
  image_.clear();
  pd_configured_ = false;
  expected_wkc_ = 0;
  reference_clock_.reset();
  dc_cyclic_ = false;
  // Neither SOEM nor IgH touch write protection; a slave left protected (by a
  // stray frame, a previous master) would refuse every write of the scan.
  if (auto r = clear_write_protection(); !r) return fail(r.error());
  // SOEM ecx_config_init order (masters.md §1.1): Init + ack, count, reset.
  const std::uint8_t init_ack[2]{static_cast<std::uint8_t>(AlState::Init) | kAlErrorBit, 0};
  if (auto r = bwr(reg::kAlControl, init_ack); !r) return fail(r.error());
  auto count = count_slaves();
  if (!count) return fail(count.error());
  if (*count == 0) return fail(MasterError::NoSlaves);
  if (*count > config_.max_slaves) return fail(MasterError::TooManySlaves);

  const std::uint8_t zero_byte[1]{0};
  const std::uint8_t event_mask[2]{0x04, 0x00};  // DL status event only
  static constexpr std::array<std::uint8_t, reg::kFmmuBlockSize> kZeros{};
  const std::uint8_t sii_force_ecat[1]{0x02};
  for (auto step : {std::pair<std::uint16_t, ConstBytes>{reg::kDlControlAlias, zero_byte},
                    {reg::kDlControlLoop, zero_byte},
                    {reg::kEcatEventMask, event_mask},
                    {reg::kRxErrorCounter, ConstBytes(kZeros.data(), 8)},
                    {reg::kFmmuBase, ConstBytes(kZeros.data(), reg::kFmmuBlockSize)},
                    {reg::kSyncManagerBase, ConstBytes(kZeros.data(), reg::kSyncManagerBlockSize)},
                    {reg::kDcActivation, zero_byte},
                    {reg::kEepromConfiguration, sii_force_ecat},
                    {reg::kEepromConfiguration, zero_byte}}) {
    // WKC not checked: ESCs differ in which of these blocks they count (masters.md §3.1).
    if (auto r = bwr(step.first, step.second); !r) return fail(r.error());
  }

  // Station addresses, their read-back, then ESC info, DL status and AL
  // status of every slave: one datagram per slave and step, as many per frame
  // as fit (issue 16 item 5: 1000 slaves in tens of frames, not thousands).
  slaves_.resize(*count);
  constexpr std::size_t kWord = sizeof(std::uint16_t);  // 0x0010 station address, 0x0110 DL status
  DatagramBatch batch;
  for (std::size_t p = 0; p < *count; ++p) {
    std::uint8_t a[kWord];
    store_le(a, static_cast<std::uint16_t>(config_.first_station_address + p));
    batch.add(Command::Apwr,
              device_address(auto_increment_adp(static_cast<std::uint16_t>(p)), reg::kConfiguredStationAddress), a);
  }
  if (auto r = batch.exchange(link_); !r) return fail(r.error());
  if (!batch.all_wkc(1)) return fail(MasterError::WorkingCounter);
  batch.clear();
  for (std::size_t p = 0; p < *count; ++p) {
    batch.add_zeros(Command::Aprd,
                    device_address(auto_increment_adp(static_cast<std::uint16_t>(p)), reg::kConfiguredStationAddress),
                    kWord);
  }
  if (auto r = batch.exchange(link_); !r) return fail(r.error());
  if (!batch.all_wkc(1)) return fail(MasterError::WorkingCounter);
  for (std::size_t p = 0; p < *count; ++p) {
    slaves_[p].position = static_cast<std::uint16_t>(p);
    slaves_[p].station_address = load_le<std::uint16_t>(batch.data(p).data());
  }
  batch.clear();
  for (const SlaveInfo& s : slaves_) {
    batch.add_zeros(Command::Fprd, device_address(s.station_address, reg::kType), reg::kEscInfoLength);
    batch.add_zeros(Command::Fprd, device_address(s.station_address, reg::kDlStatus), kWord);
    batch.add_zeros(Command::Fprd, device_address(s.station_address, reg::kAlStatus), reg::kAlStatusReadLength);
  }
  if (auto r = batch.exchange(link_); !r) return fail(r.error());
  if (!batch.all_wkc(1)) return fail(MasterError::WorkingCounter);
  for (std::size_t p = 0; p < *count; ++p) {
    SlaveInfo& s = slaves_[p];
    ByteReader rd(batch.data(3 * p));
    s.esc.type = rd.u8();
    s.esc.revision = rd.u8();
    s.esc.build = rd.u16();
    s.esc.fmmus = rd.u8();
    s.esc.sync_managers = rd.u8();
    s.esc.ram_kib = rd.u8();
    s.esc.port_descriptor = rd.u8();
    s.esc.features = rd.u16();
    s.dl_status = load_le<std::uint16_t>(batch.data(3 * p + 1).data());
    const ConstBytes al = batch.data(3 * p + 2);
    s.al.raw = load_le<std::uint16_t>(al.data());
    s.al.code = load_le<std::uint16_t>(al.data() + (reg::kAlStatusCode - reg::kAlStatus));
  }
  if (auto r = read_sii_images(); !r) return fail(r.error());
  for (std::size_t p = 0; p < *count; ++p) {
    SlaveInfo& s = slaves_[p];
    auto parsed = parse_sii(s.sii_image);
    if (!parsed) return fail(MasterError::SiiInvalid);
    s.sii = std::move(*parsed);
    if (s.esc.has_dc() && !reference_clock_) reference_clock_ = p;
  }
  std::vector<TopologyInput> in(slaves_.size());
  for (std::size_t p = 0; p < slaves_.size(); ++p) in[p].dl_status = slaves_[p].dl_status;
  const std::vector<SlaveTopology> topology = compute_topology(in);
  for (std::size_t p = 0; p < slaves_.size(); ++p) slaves_[p].topology = topology[p];
  return slaves_.size();
}

}  // namespace ecat::master
