#include "start_line.hpp"

#include "master/coe_client.hpp"

namespace line {
namespace {

constexpr std::uint16_t kIdentityObject = 0x1018;  // CiA 301 §7.5.2.21
constexpr std::uint8_t kVendorId = 1;
constexpr std::uint8_t kProductCode = 2;

std::string at(std::size_t slave, const char* step) {
  return "slave " + std::to_string(slave + 1) + ": " + step;
}

ecat::Expected<void, std::string> enter(ecat::master::Master& master, std::size_t slave,
                                        ecat::master::AlState state, const char* step) {
  auto st = master.request_state(slave, state);
  if (!st) return ecat::fail(at(slave, step) + ": " + std::string(ecat::master::describe(st.error())));
  if (st->error()) return ecat::fail(at(slave, step) + ": refused, AL status code " + std::to_string(st->code));
  return {};
}

}  // namespace

ecat::Expected<std::vector<Station>, std::string> start_line(ecat::master::Master& master) {
  auto count = master.scan();
  if (!count) return ecat::fail("scan: " + std::string(ecat::master::describe(count.error())));
  std::vector<Station> stations;
  for (std::size_t i = 0; i < *count; ++i) {
    if (!master.configure_mailbox(i)) return ecat::fail(at(i, "mailbox set-up"));
    if (auto ok = enter(master, i, ecat::master::AlState::PreOp, "PreOp"); !ok) return ecat::fail(ok.error());
    ecat::master::CoeClient coe(master, i);
    auto vendor = coe.upload_value(kIdentityObject, kVendorId);
    auto product = coe.upload_value(kIdentityObject, kProductCode);
    if (!vendor || !product) return ecat::fail(at(i, "1018h upload"));
    if (!coe.read_pdo_sizes()) return ecat::fail(at(i, "PDO sizes"));
    stations.push_back({master.slave(i).station_address, *vendor, *product});
  }
  if (!master.configure_process_data()) return ecat::fail("process data set-up");
  for (std::size_t i = 0; i < *count; ++i) {
    if (auto ok = enter(master, i, ecat::master::AlState::SafeOp, "SafeOp"); !ok) return ecat::fail(ok.error());
  }
  (void)master.exchange_process_data();  // valid outputs before Op (ETG.1000.6 §6.4.1)
  for (std::size_t i = 0; i < *count; ++i) {
    if (auto ok = enter(master, i, ecat::master::AlState::Op, "Op"); !ok) return ecat::fail(ok.error());
  }
  return stations;
}

}  // namespace line
