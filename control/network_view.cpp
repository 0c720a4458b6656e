#include "control/network_view.hpp"

#include <string>

#include "common/le.hpp"
#include "esc/al_status_code.hpp"
#include "esc/esm.hpp"
#include "esc/register_bits.hpp"
#include "esc/registers.hpp"
#include "slave/chain.hpp"

namespace ecat::control {
namespace {

using nlohmann::json;

// 0x0300 + 2n: invalid frame counter of port n, then its RX error counter.
constexpr std::uint16_t kRxErrorStride = 2;
// 0x0440 bit 0: process-data watchdog status (1: not expired).
constexpr std::uint8_t kWatchdogStatusOk = 0x01;

json port_view(const esc::Esc& esc, unsigned port) {
  const std::uint8_t* m = esc.memory();
  const std::uint16_t dl = load_le<std::uint16_t>(m + esc::reg::kDlStatus);
  const std::uint16_t rx = static_cast<std::uint16_t>(esc::reg::kRxErrorCounter + kRxErrorStride * port);
  return json{{"port", port},
              {"present", esc.port_present(port)},
              {"link", ((dl >> (esc::bits::kDlPhysicalLinkShift + port)) & 1) != 0},
              {"loop_closed", ((dl >> (esc::bits::kDlLoopClosedShift + 2 * port)) & 1) != 0},
              {"communication", ((dl >> (esc::bits::kDlCommunicationShift + 2 * port)) & 1) != 0},
              {"invalid_frames", m[rx]},
              {"rx_errors", m[rx + 1]},
              {"forwarded_rx_errors", m[esc::reg::kForwardedRxErrorCounter + port]},
              {"lost_links", m[esc::reg::kLostLinkCounter + port]}};
}

}  // namespace

json slave_view(const slave::VirtualSlave& slave, std::size_t position) {
  const esc::Esc& esc = slave.esc();
  const std::uint8_t* m = esc.memory();
  const od::Identity& id = slave.device().identity;
  const std::uint16_t al_status = load_le<std::uint16_t>(m + esc::reg::kAlStatus);
  const auto code = static_cast<esc::AlStatusCode>(load_le<std::uint16_t>(m + esc::reg::kAlStatusCode));
  const auto state = static_cast<esc::AlState>(al_status & esc::kAlStateMask);
  const slave::SlaveStatus st = slave.status();
  json ports = json::array();
  for (unsigned p = 0; p < esc::kMaxPorts; ++p) ports.push_back(port_view(esc, p));
  return json{
      {"position", position},
      {"name", slave.name()},
      {"device", id.name},
      {"identity",
       {{"vendor_id", id.vendor_id}, {"product_code", id.product_code}, {"revision", id.revision}, {"serial", id.serial}}},
      {"station_address", load_le<std::uint16_t>(m + esc::reg::kConfiguredStationAddress)},
      {"al_status", al_status},
      {"al_state", std::string(esc::describe(state))},
      {"al_error", (al_status & esc::kAlErrorIndication) != 0},
      {"al_status_code", static_cast<std::uint16_t>(code)},
      {"al_status_code_text", std::string(esc::describe(code))},
      {"al_control", load_le<std::uint16_t>(m + esc::reg::kAlControl)},
      {"dl_status", load_le<std::uint16_t>(m + esc::reg::kDlStatus)},
      {"ports", std::move(ports)},
      {"processing_unit_errors", m[esc::reg::kProcessingUnitErrorCounter]},
      {"pdi_errors", m[esc::reg::kPdiErrorCounter]},
      {"sync_errors", st.sync_errors},
      {"watchdog",
       {{"process_data_ok", (m[esc::reg::kWatchdogStatusProcessData] & kWatchdogStatusOk) != 0},
        {"process_data_expiries", m[esc::reg::kWatchdogCounterProcessData]},
        {"pdi_expiries", m[esc::reg::kWatchdogCounterPdi]}}},
      {"application_cycles", st.application_cycles}};
}

json peer_view(const slave::Chain& chain, std::size_t slave, unsigned port) {
  const auto peer = chain.segment().peer(slave, port);
  if (!peer) return nullptr;
  if (peer->master) return json{{"master", peer->port}};
  return json{{"slave", peer->slave}, {"port", peer->port}};
}

json slave_view(const slave::Chain& chain, std::size_t position) {
  json view = slave_view(chain[position], position);
  for (unsigned p = 0; p < esc::kMaxPorts; ++p) view["ports"][p]["peer"] = peer_view(chain, position, p);
  return view;
}

json network_view(const slave::Chain& chain) {
  json slaves = json::array();
  for (std::size_t i = 0; i < chain.size(); ++i) slaves.push_back(slave_view(chain, i));
  return json{{"slaves", std::move(slaves)}, {"frames", frames_view(chain.stats(), chain.cycle_timing())}};
}

json frames_view(const slave::ChainStats& s, const slave::CycleTiming& cycles) {
  json lateness = json::object();
  for (std::size_t b = 0; b < slave::CycleTiming::kBuckets; ++b) {
    lateness[std::string(slave::CycleTiming::kBucketNames[b])] = cycles.buckets()[b];
  }
  return json{{"received", s.frames_received},
              {"returned", s.frames_returned},
              {"malformed", s.frames_malformed},
              {"lost", s.frames_lost},
              {"stale", s.frames_stale},
              {"datagrams", s.datagrams},
              {"wkc_total", s.wkc_total},
              {"cycles", cycles.cycles()},
              {"cycle_period_ns", cycles.period().count()},
              {"lateness", std::move(lateness)},
              {"lateness_unsorted", cycles.unsorted()}};
}

}  // namespace ecat::control
