#include "control/request_handler.hpp"

#include <array>
#include <charconv>
#include <limits>

#include <fmt/format.h>

#include "control/network_view.hpp"
#include "control/object_access.hpp"
#include "control/simulated_run.hpp"
#include "esc/esc.hpp"
#include "slave/chain.hpp"
#include "slave/fault_catalogue.hpp"

namespace ecat::control {
namespace {

using nlohmann::json;

// A request refused: unwinds to handle(), which replies with it. Only on
// the control path (a request), never on the frame path.
struct Refusal {
  ControlError error;
};

[[noreturn]] void refuse(std::string_view code, std::string message) {
  throw Refusal{control_error(code, std::move(message))};
}

Refusal from(ControlError e) { return Refusal{std::move(e)}; }

// An unsigned number field: a JSON integer, or a string "0x..."/decimal.
std::optional<std::uint64_t> number_of(const json& v) {
  if (v.is_number_unsigned()) return v.get<std::uint64_t>();
  if (v.is_number_integer()) {  // a signed JSON integer (as built in C++): only its non-negative values
    const std::int64_t x = v.get<std::int64_t>();
    return x >= 0 ? std::optional<std::uint64_t>(static_cast<std::uint64_t>(x)) : std::nullopt;
  }
  if (!v.is_string()) return std::nullopt;
  std::string_view s = v.get_ref<const std::string&>();
  int base = 10;
  if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
    s.remove_prefix(2);
    base = 16;
  }
  std::uint64_t out = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out, base);
  if (ec != std::errc{} || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return out;
}

std::uint64_t field(const json& r, const char* name, std::uint64_t max, std::optional<std::uint64_t> fallback = {}) {
  const auto it = r.find(name);
  if (it == r.end()) {
    if (fallback) return *fallback;
    refuse(error_code::kBadRequest, fmt::format("\"{}\" is needed", name));
  }
  const auto n = number_of(*it);
  if (!n || *n > max) {
    refuse(error_code::kBadRequest,
           fmt::format("\"{}\": {} is not a number 0..{} (an integer, or a string \"0x...\")", name, it->dump(), max));
  }
  return *n;
}

std::size_t slave_field(const json& r, const slave::Chain& chain) {
  const std::uint64_t n = field(r, "slave", std::numeric_limits<std::uint32_t>::max());
  if (n >= chain.size()) {
    refuse(error_code::kUnknownSlave, fmt::format("slave {}: no such slave (chain has {}, positions 0..{})", n,
                                                  chain.size(), chain.size() - 1));
  }
  return static_cast<std::size_t>(n);
}

std::string fault_kind_list() {
  std::string out;
  for (const slave::FaultKind& k : slave::FaultCatalogue::kinds()) out += (out.empty() ? "" : ", ") + std::string(k.name);
  return out;
}

json fault_json(const slave::EngagedFault& f) {
  json params = json::object();
  for (const auto& [name, value] : f.request.params) params[name] = value;
  json out{{"fault", f.id}, {"kind", f.request.kind}, {"params", std::move(params)}};
  if (f.request.slave) out["slave"] = *f.request.slave;
  if (f.request.port) out["port"] = *f.request.port;
  return out;
}

}  // namespace

struct RequestHandler::Command {
  std::string_view name;
  json (RequestHandler::*run)(const json&);
};

RequestHandler::RequestHandler(slave::Chain& chain, const Clock& clock, EventQueue& events,
                               slave::FaultCatalogue* faults, SimulatedRun* sim)
    : chain_(chain), clock_(clock), events_(events), faults_(faults), sim_(sim) {
  if (faults_) {
    faults_->set_observer([this](const slave::EngagedFault& f, bool engaged) {
      json e = fault_json(f);
      e["type"] = engaged ? "fault_engaged" : "fault_cleared";
      e["time_ns"] = clock_.now().count();
      events_.push(std::move(e));
    });
  }
}

RequestHandler::~RequestHandler() {
  if (faults_) faults_->set_observer({});
}

std::string RequestHandler::handle_line(std::string_view line) {
  json request = json::parse(line, nullptr, /*allow_exceptions=*/false);
  json reply;
  if (request.is_discarded()) {
    reply = json{{"id", nullptr},
                 {"error", {{"code", error_code::kBadJson}, {"message", "the line is not one JSON value"}}}};
  } else {
    reply = handle(request);
  }
  return reply.dump(-1, ' ', false, json::error_handler_t::replace);
}

json RequestHandler::handle(const json& request) {
  json id = nullptr;
  if (request.is_object()) {
    if (auto it = request.find("id"); it != request.end()) id = *it;
  }
  try {
    return json{{"id", id}, {"result", dispatch(request)}};
  } catch (const Refusal& r) {
    return json{{"id", id}, {"error", {{"code", r.error.code}, {"message", r.error.message}}}};
  } catch (const json::exception& e) {
    return json{{"id", id}, {"error", {{"code", error_code::kBadRequest}, {"message", e.what()}}}};
  }
}

json RequestHandler::dispatch(const json& request) {
  static constexpr std::array<Command, 18> kCommands{{
      {"hello", &RequestHandler::hello},
      {"network", &RequestHandler::network},
      {"slave", &RequestHandler::slave},
      {"read", &RequestHandler::read},
      {"register", &RequestHandler::register_read},
      {"write", &RequestHandler::write},
      {"pdo", &RequestHandler::pdo},
      {"events", &RequestHandler::events_since},
      {"subscribe", &RequestHandler::streaming_only},
      {"unsubscribe", &RequestHandler::streaming_only},
      {"fault_kinds", &RequestHandler::fault_kinds},
      {"fault_engage", &RequestHandler::fault_engage},
      {"fault_clear", &RequestHandler::fault_clear},
      {"faults", &RequestHandler::faults_list},
      {"pause", &RequestHandler::pause},
      {"run", &RequestHandler::run},
      {"step", &RequestHandler::step},
      {"time", &RequestHandler::time},
  }};
  if (!request.is_object()) refuse(error_code::kBadRequest, "a request is a JSON object with \"cmd\"");
  const auto cmd = request.find("cmd");
  if (cmd == request.end() || !cmd->is_string()) {
    refuse(error_code::kBadRequest, "\"cmd\" (a string) is needed");
  }
  const std::string& name = cmd->get_ref<const std::string&>();
  for (const Command& c : kCommands) {
    if (c.name == name) return (this->*c.run)(request);
  }
  std::string known;
  for (const Command& c : kCommands) known += (known.empty() ? "" : ", ") + std::string(c.name);
  refuse(error_code::kUnknownCommand, fmt::format("unknown command '{}' (known: {})", name, known));
}

json RequestHandler::hello(const json&) {
  return json{{"protocol", kProtocolVersion},
              {"slaves", chain_.size()},
              {"faults", faults_ != nullptr},
              {"simulated", sim_ != nullptr},
              {"time_ns", clock_.now().count()},
              {"next_event", events_.next_seq()}};
}

json RequestHandler::network(const json&) {
  chain_.cycle_timing().settle();
  return network_view(chain_);
}

json RequestHandler::slave(const json& r) {
  const std::size_t i = slave_field(r, chain_);
  const slave::Chain& chain = chain_;
  return slave_view(chain, i);
}

json RequestHandler::read(const json& r) {
  const std::size_t i = slave_field(r, chain_);
  const auto index = static_cast<std::uint16_t>(field(r, "index", 0xFFFF));
  const auto sub = static_cast<std::uint8_t>(field(r, "subindex", 0xFF, 0));
  const slave::Chain& chain = chain_;
  auto v = read_object(chain[i].firmware().coe().objects(), index, sub);
  if (!v) throw from(v.error());
  return *v;
}

// An ESC register as the slave's own firmware (PDI) would read it, without
// side effects: no AL event acknowledged, no counter cleared, the DC block
// (0x0900-0x09FF: system time, 0x092C difference) at the ESC's latest time.
json RequestHandler::register_read(const json& r) {
  const std::size_t i = slave_field(r, chain_);
  const auto address = static_cast<std::uint16_t>(field(r, "address", esc::Esc::kRegisterEnd - 1));
  const std::uint64_t size = field(r, "size", sizeof(std::uint64_t), sizeof(std::uint16_t));
  if (size != 1 && size != 2 && size != 4 && size != 8) {
    refuse(error_code::kBadRequest, fmt::format("\"size\": {} is not 1, 2, 4 or 8 bytes", size));
  }
  if (address + size > esc::Esc::kRegisterEnd) {
    refuse(error_code::kBadRequest,
           fmt::format("register 0x{:04X} + {} bytes goes past the registers (0x0000-0x{:04X})", address, size,
                       esc::Esc::kRegisterEnd - 1));
  }
  const esc::Esc& esc = chain_[i].esc();
  std::uint64_t value = 0;
  for (std::uint64_t k = 0; k < size; k += sizeof(std::uint16_t)) {
    const std::uint16_t word = esc.register_u16(static_cast<std::uint16_t>(address + k));
    value |= static_cast<std::uint64_t>(size == 1 ? word & 0xFFU : word) << (8 * k);
  }
  return json{{"address", address},
              {"size", size},
              {"value", value},
              {"hex", fmt::format("{:0{}X}", value, 2 * size)}};
}

json RequestHandler::write(const json& r) {
  const std::size_t i = slave_field(r, chain_);
  const auto index = static_cast<std::uint16_t>(field(r, "index", 0xFFFF));
  const auto sub = static_cast<std::uint8_t>(field(r, "subindex", 0xFF, 0));
  if (!r.contains("value")) refuse(error_code::kBadRequest, "\"value\" is needed");
  auto v = write_object(chain_[i].firmware().coe().objects(), index, sub, r["value"]);
  if (!v) throw from(v.error());
  return *v;
}

json RequestHandler::pdo(const json& r) {
  const std::size_t i = slave_field(r, chain_);
  slave::VirtualSlave& s = chain_[i];
  coe::ObjectStore& store = s.firmware().coe().objects();
  const auto name = r.find("name");
  if (name == r.end()) return json{{"entries", list_pdo_entries(s.device(), store)}};
  if (!name->is_string()) refuse(error_code::kBadRequest, "\"name\" is a string");
  auto found = find_pdo_entry(s.device(), name->get_ref<const std::string&>());
  if (!found) throw from(found.error());
  const od::PdoEntry& e = *found->entry;
  auto v = r.contains("value") ? write_object(store, e.index, e.subindex, r["value"])
                               : read_object(store, e.index, e.subindex);
  if (!v) throw from(v.error());
  (*v)["pdo"] = found->pdo;
  (*v)["direction"] = found->rx ? "rx" : "tx";
  return *v;
}

json RequestHandler::events_since(const json& r) {
  const std::uint64_t since = field(r, "since", std::numeric_limits<std::uint64_t>::max(), 0);
  const auto max = static_cast<std::size_t>(field(r, "max", kMaxEventsPerReply, 1000));
  return events_.since(since, max);
}

json RequestHandler::streaming_only(const json& r) {
  refuse(error_code::kNotStreaming,
         fmt::format("'{}' needs a stream transport (the socket server); poll with \"events\" instead",
                     r["cmd"].get<std::string>()));
}

slave::FaultCatalogue& RequestHandler::need_faults() {
  if (!faults_) refuse(error_code::kNoFaults, "this network has no fault catalogue");
  return *faults_;
}

json RequestHandler::fault_kinds(const json&) {
  json kinds = json::array();
  for (const slave::FaultKind& k : slave::FaultCatalogue::kinds()) {
    json params = json::array();
    for (const slave::FaultParam& p : k.params) {
      params.push_back({{"name", p.name}, {"meaning", p.meaning}, {"required", p.required}});
    }
    kinds.push_back({{"name", k.name},
                     {"description", k.description},
                     {"needs_slave", k.needs_slave},
                     {"takes_slave", k.takes_slave || k.needs_slave},
                     {"needs_port", k.needs_port},
                     {"params", std::move(params)}});
  }
  return json{{"kinds", std::move(kinds)}};
}

json RequestHandler::fault_engage(const json& r) {
  slave::FaultCatalogue& faults = need_faults();
  const auto kind = r.find("kind");
  if (kind == r.end() || !kind->is_string()) refuse(error_code::kBadRequest, "\"kind\" (a string) is needed");
  slave::FaultRequest request;
  request.kind = kind->get<std::string>();
  if (!slave::FaultCatalogue::find_kind(request.kind)) {
    refuse(error_code::kUnknownFault,
           fmt::format("unknown fault kind '{}' (known: {})", request.kind, fault_kind_list()));
  }
  if (r.contains("slave")) request.slave = slave_field(r, chain_);
  if (r.contains("port")) request.port = static_cast<unsigned>(field(r, "port", 0xFF));
  if (const auto p = r.find("params"); p != r.end()) {
    if (!p->is_object()) refuse(error_code::kBadRequest, "\"params\" is an object of named integers");
    for (const auto& [name, value] : p->items()) {
      if (value.is_boolean()) {
        request.params[name] = value.get<bool>() ? 1 : 0;
      } else if (value.is_number_integer()) {
        if (value.is_number_unsigned() && value.get<std::uint64_t>() > std::uint64_t{INT64_MAX}) {
          refuse(error_code::kBadRequest, fmt::format("params.{}: {} is too large", name, value.dump()));
        }
        request.params[name] = value.get<std::int64_t>();
      } else {
        refuse(error_code::kBadRequest, fmt::format("params.{}: {} is not an integer", name, value.dump()));
      }
    }
  }
  auto id = faults.engage(request);
  if (!id) refuse(error_code::kFaultRefused, id.error());
  return json{{"fault", *id}};
}

json RequestHandler::fault_clear(const json& r) {
  slave::FaultCatalogue& faults = need_faults();
  if (const auto all = r.find("all"); all != r.end() && all->is_boolean() && all->get<bool>()) {
    const std::size_t n = faults.engaged().size();
    faults.clear_all();
    return json{{"cleared", n}};
  }
  const auto id = static_cast<slave::FaultId>(field(r, "fault", std::numeric_limits<slave::FaultId>::max()));
  bool known = false;
  for (const slave::EngagedFault& f : faults.engaged()) known = known || f.id == id;
  if (!known) refuse(error_code::kUnknownFault, fmt::format("fault {}: not engaged (see \"faults\")", id));
  if (auto ok = faults.clear(id); !ok) refuse(error_code::kFaultRefused, ok.error());
  return json{{"cleared", 1}};
}

bool RequestHandler::faults_engaged() const { return faults_ != nullptr && !faults_->engaged().empty(); }

json RequestHandler::faults_list(const json&) {
  json list = json::array();
  for (const slave::EngagedFault& f : need_faults().engaged()) list.push_back(fault_json(f));
  return json{{"faults", std::move(list)}};
}

SimulatedRun& RequestHandler::need_sim() {
  if (!sim_) refuse(error_code::kNotSimulated, "this network runs on the wall clock: pause, step and run need simulated time");
  return *sim_;
}

json RequestHandler::pause(const json& r) {
  need_sim().pause();
  return time(r);
}

json RequestHandler::run(const json& r) {
  need_sim().run();
  return time(r);
}

json RequestHandler::step(const json& r) {
  SimulatedRun& sim = need_sim();
  sim.step(field(r, "cycles", kMaxStepCycles, 1));
  return time(r);
}

json RequestHandler::time(const json&) {
  json out{{"time_ns", clock_.now().count()}, {"simulated", sim_ != nullptr}};
  if (sim_) {
    out["paused"] = sim_->paused();
    out["cycles"] = sim_->cycles();
    out["period_ns"] = sim_->period().count();
  }
  return out;
}

}  // namespace ecat::control
