#include "web/live_snapshot.hpp"

#include <charconv>
#include <cstring>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

#include "control/network_view.hpp"
#include "control/request_handler.hpp"
#include "esc/registers.hpp"
#include "od/axis_layout.hpp"
#include "od/firmware.hpp"
#include "slave/chain.hpp"

namespace ecat::web {
namespace {

using nlohmann::json;

// CiA 402 objects the page shows for each axis (CiA 402-2), as axis-1
// indices: axis n keeps them where the device's od::AxisLayout says.
struct DriveObject {
  std::string_view key;
  std::uint16_t index;
};
constexpr std::uint16_t kStatusword = 0x6041;
// A drive whose device file declares no axes has one.
const od::AxisLayout kOneAxis{};
constexpr std::array<DriveObject, 8> kDriveObjects{{
    {"statusword", kStatusword},
    {"mode", 0x6061},                // modes of operation display
    {"position_demand", 0x6062},     // position demand value
    {"position_actual", 0x6064},     // position actual value
    {"velocity_demand", 0x606B},     // velocity demand value
    {"velocity_actual", 0x606C},     // velocity actual value
    {"torque_demand", 0x6074},       // torque demand
    {"torque_actual", 0x6077},       // torque actual value
}};

// The ESC memory a slave's view is made of (control::slave_view): station
// address, DL status, AL control, AL status and code, the error counters
// 0x0300-0x0313, the watchdog status and counters.
struct RegisterRange {
  std::uint16_t address;
  std::uint16_t size;
};
constexpr std::array<RegisterRange, 6> kViewRegisters{{
    {esc::reg::kConfiguredStationAddress, 2},
    {esc::reg::kDlStatus, 2},
    {esc::reg::kAlControl, 2},
    {esc::reg::kAlStatus, 6},  // AL status, reserved, AL status code
    {esc::reg::kRxErrorCounter, 20},  // up to the lost-link counters
    {esc::reg::kWatchdogStatusProcessData, 4},
}};
constexpr std::size_t register_bytes() {
  std::size_t n = 0;
  for (const RegisterRange& r : kViewRegisters) n += r.size;
  return n;
}
static_assert(register_bytes() == LiveSnapshot::kRegisterBytes);
constexpr std::string_view kCyclesKey = "application_cycles";
// Peer kinds in the fingerprint.
constexpr std::uint8_t kNoPeer = 0;
constexpr std::uint8_t kPeerMaster = 1;
constexpr std::uint8_t kPeerSlave = 2;

json result_of(control::RequestHandler& h, json request) {
  json reply = h.handle(request);
  return reply.contains("result") ? std::move(reply["result"]) : json();
}

template <typename T>
void append_number(std::string& out, T v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

void append_key(std::string& out, std::string_view key) {
  out += '"';
  out += key;
  out += "\":";
}

}  // namespace

const std::vector<bool>& LiveSnapshot::drives(std::size_t slaves) {
  if (!drives_) {
    drives_.emplace(slaves, false);
    slave::Chain& chain = handler_.chain();
    for (std::size_t i = 0; i < slaves && i < chain.size(); ++i) {
      (*drives_)[i] = od::runs_firmware(chain[i].device()) &&
                      chain[i].firmware().coe().objects().slot(kStatusword, 0) != nullptr;
    }
  }
  return *drives_;
}

LiveSnapshot::Fingerprint LiveSnapshot::fingerprint(std::size_t i) const {
  const slave::Chain& chain = handler_.chain();
  const slave::VirtualSlave& s = chain[i];
  const std::uint8_t* m = s.esc().memory();
  Fingerprint f{};
  std::size_t at = 0;
  for (const RegisterRange& r : kViewRegisters) {
    std::memcpy(f.data() + at, m + r.address, r.size);
    at += r.size;
  }
  const std::uint32_t sync_errors = s.status().sync_errors;
  std::memcpy(f.data() + at, &sync_errors, sizeof sync_errors);
  at += sizeof sync_errors;
  for (unsigned p = 0; p < esc::kMaxPorts; ++p) {
    const auto peer = chain.segment().peer(i, p);
    const std::size_t peer_slave = peer && !peer->master ? peer->slave : 0;
    f[at++] = s.esc().port_present(p) ? 1 : 0;
    f[at++] = !peer ? kNoPeer : peer->master ? kPeerMaster : kPeerSlave;
    f[at++] = static_cast<std::uint8_t>(peer_slave);
    f[at++] = static_cast<std::uint8_t>(peer_slave >> 8);
    f[at++] = peer ? static_cast<std::uint8_t>(peer->port) : 0;
  }
  return f;
}

// "frames":{...}, as control::frames_view has them, written as numbers.
void LiveSnapshot::append_frames(const slave::ChainStats& s, const slave::CycleTiming& cycles) {
  const std::array<std::pair<std::string_view, std::uint64_t>, 8> counters{{{"received", s.frames_received},
                                                                            {"returned", s.frames_returned},
                                                                            {"malformed", s.frames_malformed},
                                                                            {"lost", s.frames_lost},
                                                                            {"stale", s.frames_stale},
                                                                            {"datagrams", s.datagrams},
                                                                            {"wkc_total", s.wkc_total},
                                                                            {"cycles", cycles.cycles()}}};
  append_key(text_, "frames");
  char sep = '{';
  for (const auto& [key, value] : counters) {
    text_ += sep;
    sep = ',';
    append_key(text_, key);
    append_number(text_, value);
  }
  text_ += ',';
  append_key(text_, "cycle_period_ns");
  append_number(text_, cycles.period().count());
  text_ += ',';
  append_key(text_, "lateness");
  sep = '{';
  for (std::size_t b = 0; b < slave::CycleTiming::kBuckets; ++b) {
    text_ += sep;
    sep = ',';
    append_key(text_, slave::CycleTiming::kBucketNames[b]);
    append_number(text_, cycles.buckets()[b]);
  }
  text_ += "},";
  append_key(text_, "lateness_unsorted");
  append_number(text_, cycles.unsorted());
  text_ += "},";
}

// "slaves":[...]: each view from its kept text when its fingerprint is
// unchanged, with the application-cycle counter written in front.
void LiveSnapshot::append_slaves() {
  const slave::Chain& chain = handler_.chain();
  slaves_.resize(chain.size());
  append_key(text_, "slaves");
  text_ += '[';
  for (std::size_t i = 0; i < chain.size(); ++i) {
    SlaveText& kept = slaves_[i];
    const Fingerprint f = fingerprint(i);
    if (!kept.valid || f != kept.fingerprint) {
      json view = control::slave_view(chain, i);
      view.erase(std::string(kCyclesKey));
      kept.body = view.dump();
      kept.body.erase(0, 1);  // the opening brace: the counter goes first
      kept.fingerprint = f;
      kept.valid = true;
      ++views_built_;
    }
    if (i > 0) text_ += ',';
    text_ += '{';
    append_key(text_, kCyclesKey);
    append_number(text_, chain[i].status().application_cycles);
    if (kept.body != "}") text_ += ',';
    text_ += kept.body;
  }
  text_ += ']';
}

// "drives":[...]: one entry per axis of each drive ("slave", "axis" from 1),
// its objects straight from the object store, as the "read" command would
// give their values (8 objects of 100 drives through "read" took about 8 ms
// of the loop's time per snapshot).
void LiveSnapshot::append_drives(const std::vector<bool>& is_drive) {
  slave::Chain& chain = handler_.chain();
  append_key(text_, "drives");
  text_ += '[';
  bool first = true;
  for (std::size_t i = 0; i < is_drive.size(); ++i) {
    if (!is_drive[i]) continue;
    // (the firmware is looked up each time: a power cycle replaces it)
    const coe::ObjectStore& store = chain[i].firmware().coe().objects();
    const auto& profile = chain[i].device().drive;
    const od::AxisLayout& layout = profile ? profile->axes : kOneAxis;
    for (unsigned axis = 1; axis <= layout.axes; ++axis) {
      if (!first) text_ += ',';
      first = false;
      text_ += '{';
      append_key(text_, "slave");
      append_number(text_, i);
      text_ += ',';
      append_key(text_, "axis");
      append_number(text_, axis);
      for (const DriveObject& o : kDriveObjects) {
        text_ += ',';
        append_key(text_, o.key);
        const coe::ObjectStore::Slot* s = store.slot(layout.object_index(axis, o.index), 0);
        if (s == nullptr) {
          text_ += "null";
        } else {
          append_number(text_, store.get<std::int64_t>(*s));
        }
      }
      text_ += '}';
    }
  }
  text_ += ']';
}

const std::string& LiveSnapshot::take() {
  slave::Chain& chain = handler_.chain();
  text_.clear();
  text_ += '{';
  append_drives(drives(chain.size()));
  text_ += ',';
  append_key(text_, "faults");
  if (handler_.faults_engaged()) {
    text_ += result_of(handler_, {{"cmd", "faults"}})["faults"].dump();
  } else {
    text_ += "[]";  // what the "faults" command lists, with nothing engaged or no catalogue
  }
  text_ += ',';
  append_key(text_, "network");
  text_ += '{';
  chain.cycle_timing().settle();
  append_frames(chain.stats(), chain.cycle_timing());
  append_slaves();
  text_ += "},";
  append_key(text_, "time_ns");  // the "time" command's
  append_number(text_, handler_.clock().now().count());
  text_ += '}';
  return text_;
}

}  // namespace ecat::web
