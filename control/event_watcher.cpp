#include "control/event_watcher.hpp"

#include <string>

#include "common/le.hpp"
#include "control/object_access.hpp"
#include "esc/al_status_code.hpp"
#include "esc/esm.hpp"
#include "esc/register_bits.hpp"
#include "esc/registers.hpp"
#include "slave/chain.hpp"

namespace ecat::control {
namespace {

using nlohmann::json;

std::string state_name(std::uint16_t al) {
  return std::string(esc::describe(static_cast<esc::AlState>(al & esc::kAlStateMask)));
}

json event(std::string_view type, std::size_t slave, Nanoseconds now) {
  return json{{"type", std::string(type)}, {"slave", slave}, {"time_ns", now.count()}};
}

// Reports the entries numbered [from, to) of one of a slave's recent logs
// (coe/recent_log.hpp) as events of `type`, each filled by `fill`, and the
// ones the log no longer holds as one events_lost event.
template <typename Log, typename Fill>
void drain(const Log& log, std::uint64_t from, std::uint64_t to, std::string_view type, std::size_t slave,
           Nanoseconds now, EventQueue& queue, Fill fill) {
  if (to <= from) return;
  for (std::uint64_t n = from; n < to; ++n) {
    auto entry = log.at(n);
    if (!entry) continue;
    json e = event(type, slave, now);
    fill(e, *entry);
    queue.push(std::move(e));
  }
  if (to - from > log.kCapacity) {
    json e = event("events_lost", slave, now);
    e["what"] = type;
    e["count"] = to - from - log.kCapacity;
    queue.push(std::move(e));
  }
}

}  // namespace

EventWatcher::EventWatcher(slave::Chain& chain) : chain_(chain) { rebase(); }

EventWatcher::Seen EventWatcher::read(std::size_t i) const {
  const slave::Chain& chain = chain_;
  const slave::VirtualSlave& s = chain[i];
  const std::uint8_t* m = s.esc().memory();
  const coe::CoeServer& coe = s.firmware().coe();
  return Seen{load_le<std::uint16_t>(m + esc::reg::kAlStatus),
              load_le<std::uint16_t>(m + esc::reg::kAlStatusCode),
              load_le<std::uint16_t>(m + esc::reg::kAlControl),
              load_le<std::uint16_t>(m + esc::reg::kDlStatus),
              coe.objects().service_writes().count(),
              coe.emergency().sent().count()};
}

void EventWatcher::rebase() {
  seen_.clear();
  for (std::size_t i = 0; i < chain_.size(); ++i) seen_.push_back(read(i));
}

void EventWatcher::sample(Nanoseconds now, EventQueue& queue) {
  const slave::Chain& chain = chain_;
  for (std::size_t i = 0; i < seen_.size(); ++i) {
    const Seen now_seen = read(i);
    Seen& was = seen_[i];
    if (now_seen == was) continue;  // the usual sample: nothing changed
    if (now_seen.al_control != was.al_control) {
      json e = event("al_control", i, now);
      e["requested"] = state_name(now_seen.al_control);
      e["error_ack"] = (now_seen.al_control & esc::kAlErrorAck) != 0;
      e["al_control"] = now_seen.al_control;
      queue.push(std::move(e));
    }
    if (now_seen.al_status != was.al_status || now_seen.al_code != was.al_code) {
      json e = event("al_state", i, now);
      e["from"] = state_name(was.al_status);
      e["to"] = state_name(now_seen.al_status);
      e["error"] = (now_seen.al_status & esc::kAlErrorIndication) != 0;
      e["al_status_code"] = now_seen.al_code;
      e["al_status_code_text"] = std::string(esc::describe(static_cast<esc::AlStatusCode>(now_seen.al_code)));
      queue.push(std::move(e));
    }
    for (unsigned p = 0; p < esc::kMaxPorts; ++p) {
      const unsigned bit = esc::bits::kDlPhysicalLinkShift + p;
      const bool up = ((now_seen.dl_status >> bit) & 1) != 0;
      if (up != (((was.dl_status >> bit) & 1) != 0)) {
        json e = event("link", i, now);
        e["port"] = p;
        e["up"] = up;
        queue.push(std::move(e));
      }
    }
    const coe::CoeServer& coe = chain[i].firmware().coe();
    // A power cycle starts the firmware's logs afresh: nothing to report then.
    drain(coe.objects().service_writes(), was.sdo_writes, now_seen.sdo_writes, "sdo_write", i, now, queue,
          [&](json& e, const auto& w) {
            e["index"] = w.index;
            e["subindex"] = w.subindex;
            if (auto v = read_object(coe.objects(), w.index, w.subindex)) e["value"] = (*v)["value"];
          });
    drain(coe.emergency().sent(), was.emergencies, now_seen.emergencies, "emergency", i, now, queue,
          [](json& e, const auto& m) {
            e["error_code"] = m.error_code;
            e["error_register"] = m.error_register;
          });
    was = now_seen;
  }
}

}  // namespace ecat::control
