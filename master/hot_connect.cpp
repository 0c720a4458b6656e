// Hot connect: a slave that came back fresh at its position is addressed and
// configured again (SOEM ec_recover_slave + ec_reconfig_slave; docs/master.md
// "Hot connect").
#include <array>

#include "common/le.hpp"
#include "master/datagram_batch.hpp"
#include "master/master.hpp"
#include "master/registers.hpp"
#include "master/sii.hpp"

namespace ecat::master {

namespace {
constexpr std::size_t kWord = sizeof(std::uint16_t);
// SII words 8-13: vendor ID, product code, revision (sii-eeprom.md §1).
constexpr std::size_t kIdentityBytes = 12;
}  // namespace

Expected<void, MasterError> Master::write_station_address(std::uint16_t position, std::uint16_t station) {
  std::uint8_t a[kWord];
  store_le(a, station);
  auto wkc = transact(Command::Apwr, device_address(auto_increment_adp(position), reg::kConfiguredStationAddress), a);
  if (!wkc) return fail(wkc.error());
  if (*wkc != 1) return fail(MasterError::WorkingCounter);
  return {};
}

Expected<bool, MasterError> Master::readdress(std::size_t slave) {
  if (slave >= slaves_.size()) return fail(MasterError::InvalidArgument);
  const SlaveInfo& s = slaves_[slave];
  std::uint8_t a[kWord]{};
  auto wkc = transact(Command::Aprd, device_address(auto_increment_adp(s.position), reg::kConfiguredStationAddress), a);
  if (!wkc) return fail(wkc.error());
  if (*wkc != 1) return fail(MasterError::WorkingCounter);  // nothing at the position (yet)
  if (load_le<std::uint16_t>(a) == s.station_address) return false;
  // Another address (0 after a power cycle): is it the device the scan found?
  if (auto ok = write_station_address(s.position, kTemporaryStation); !ok) return fail(ok.error());
  std::array<std::uint8_t, kIdentityBytes> id{};
  for (std::size_t at = 0; at < id.size();) {
    std::array<std::uint8_t, sii::kReadMax> chunk{};
    auto got = sii_read(kTemporaryStation, static_cast<std::uint16_t>(sii::kVendorId + at / kWord), chunk);
    if (!got) {
      (void)write_station_address(s.position, 0);
      return fail(got.error());
    }
    for (std::size_t i = 0; i < *got && at < id.size(); ++i) id[at++] = chunk[i];
  }
  if (load_le<std::uint32_t>(id.data()) != s.sii.vendor_id || load_le<std::uint32_t>(id.data() + 4) != s.sii.product_code ||
      load_le<std::uint32_t>(id.data() + 8) != s.sii.revision) {
    (void)write_station_address(s.position, 0);
    return fail(MasterError::WrongSlave);
  }
  if (auto ok = write_station_address(s.position, s.station_address); !ok) return fail(ok.error());
  return true;
}

Expected<void, MasterError> Master::write_process_data_config(std::size_t slave) {
  if (slave >= slaves_.size()) return fail(MasterError::InvalidArgument);
  if (!pd_configured_) return fail(MasterError::NotConfigured);
  DatagramBatch batch;
  if (!add_process_data_config(batch, slaves_[slave])) return fail(MasterError::InvalidArgument);
  if (auto r = batch.exchange(link_); !r) return fail(r.error());
  if (!batch.all_wkc(1)) return fail(MasterError::WorkingCounter);
  return {};
}

}  // namespace ecat::master
