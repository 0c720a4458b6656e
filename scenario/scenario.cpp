#include "scenario/scenario.hpp"

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "scenario/yaml_json.hpp"

namespace ecat::scenario {
namespace {

using nlohmann::json;

// The event types of the control interface (docs/control.md "Events").
constexpr std::array<std::string_view, 8> kEventTypes = {"al_control",      "al_state",      "link",
                                                         "sdo_write",       "emergency",     "fault_engaged",
                                                         "fault_cleared",   "events_lost"};
constexpr std::array<std::string_view, 3> kScenarioKeys = {"name", "timeout", "steps"};
constexpr std::array<std::string_view, 11> kStepKeys = {"name", "after",      "at",     "after_frames",
                                                        "when", "do",         "save",   "expect",
                                                        "expect_not", "within", "for"};
constexpr std::array<std::string_view, 5> kValueKeys = {"read", "mask", "equals", "min", "max"};

template <std::size_t N>
std::string join(const std::array<std::string_view, N>& words) {
  std::string list;
  for (std::string_view w : words) list += (list.empty() ? "" : ", ") + std::string(w);
  return list;
}

struct Problem {
  std::string text;
};

class Parser {
 public:
  explicit Parser(std::string_view file) : file_(file) {}

  std::string where(const YAML::Mark& m) const {
    if (m.is_null()) return std::string(file_);
    return fmt::format("{}:{}:{}", file_, m.line + 1, m.column + 1);
  }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) const {
    throw Problem{fmt::format("{}: {}", where(n.Mark()), what)};
  }

  template <std::size_t N>
  void only_keys(const YAML::Node& map, const std::array<std::string_view, N>& keys, std::string_view what) const {
    for (const auto& kv : map) {
      const std::string k = kv.first.Scalar();
      bool known = false;
      for (std::string_view key : keys) known = known || key == k;
      if (!known) fail(kv.first, fmt::format("unknown key '{}' in {} (known: {})", k, what, join(keys)));
    }
  }

  Nanoseconds duration(const YAML::Node& n, std::string_view key) const {
    if (!n.IsScalar()) fail(n, fmt::format("'{}' must be a duration such as 250ms or 2s", key));
    auto d = parse_duration(n.Scalar());
    if (!d) fail(n, fmt::format("'{}': {}", key, d.error()));
    return *d;
  }

  Match match(const YAML::Node& n, std::string_view key) const {
    if (!n.IsMap()) fail(n, fmt::format("'{}' must be a map: an event ({{type: al_state, ...}}) or a value "
                                        "({{read: {{slave: 0, index: 0x6041}}, equals: ...}})",
                                        key));
    Match m;
    if (n["read"]) {
      only_keys(n, kValueKeys, key);
      m.kind = Match::Kind::Value;
      const YAML::Node read = n["read"];
      // An object (index, subindex) or an ESC register (register, size).
      if (!read.IsMap() || !read["slave"] || (!read["index"] == !read["register"])) {
        fail(read, "'read' needs slave and either index (an object) or register (an ESC register)");
      }
      m.read = to_json(read);
      if (read["register"]) {
        m.read["address"] = m.read["register"];
        m.read.erase("register");
        m.read["cmd"] = "register";
      } else {
        m.read["cmd"] = "read";
      }
      if (n["mask"]) {
        const json mask = to_json(n["mask"]);
        if (!mask.is_number_integer() || mask.get<std::int64_t>() < 0) fail(n["mask"], "'mask' must be an integer");
        m.mask = mask.get<std::uint64_t>();
      }
      if (n["equals"]) m.equals = to_json(n["equals"]);
      for (const char* bound : {"min", "max"}) {
        if (!n[bound]) continue;
        const json b = to_json(n[bound]);
        if (!b.is_number()) fail(n[bound], fmt::format("'{}' must be a number", bound));
        (std::string_view(bound) == "min" ? m.min : m.max) = b.get<double>();
      }
      if (m.equals.is_null() && !m.min && !m.max) fail(n, "a value match needs 'equals', 'min' or 'max'");
      if (m.mask && !m.equals.is_null() && !m.equals.is_number_integer()) {
        fail(n, "'mask' goes with an integer 'equals' (or with 'min'/'max')");
      }
      return m;
    }
    if (!n["type"]) fail(n, fmt::format("'{}' needs 'type' (an event) or 'read' (a value)", key));
    const std::string type = n["type"].Scalar();
    bool known = false;
    for (std::string_view t : kEventTypes) known = known || t == type;
    if (!known) fail(n["type"], fmt::format("unknown event type '{}' (known: {})", type, join(kEventTypes)));
    m.kind = Match::Kind::Event;
    m.event = to_json(n);
    return m;
  }

  Step step(const YAML::Node& n, std::size_t index) const {
    if (!n.IsMap()) fail(n, "a step must be a map (name, a trigger, and do / expect / expect_not)");
    only_keys(n, kStepKeys, "a step");
    Step s;
    s.line = n.Mark().line + 1;
    int triggers = 0;
    if (n["after"]) {
      s.after = duration(n["after"], "after");
      ++triggers;
    }
    if (n["at"]) {
      s.at = duration(n["at"], "at");
      ++triggers;
    }
    if (n["after_frames"]) {
      const json f = to_json(n["after_frames"]);
      if (!f.is_number_integer() || f.get<std::int64_t>() < 0) fail(n["after_frames"], "'after_frames' must be a count");
      s.after_frames = f.get<std::uint64_t>();
      ++triggers;
    }
    if (n["when"]) {
      s.when = match(n["when"], "when");
      ++triggers;
    }
    if (triggers > 1) fail(n, "a step has one trigger at most (after, at, after_frames or when)");
    int actions = 0;
    if (n["do"]) {
      const YAML::Node d = n["do"];
      if (!d.IsMap() || !d["cmd"]) fail(d, "'do' must be a control request with 'cmd' (docs/control.md)");
      s.action = Step::Action::Do;
      s.request = to_json(d);
      ++actions;
    }
    if (n["expect"]) {
      s.action = Step::Action::Expect;
      s.match = match(n["expect"], "expect");
      ++actions;
    }
    if (n["expect_not"]) {
      s.action = Step::Action::ExpectNot;
      s.match = match(n["expect_not"], "expect_not");
      ++actions;
    }
    if (actions > 1) fail(n, "a step has one of do, expect and expect_not");
    if (n["save"]) {
      if (s.action != Step::Action::Do) fail(n["save"], "'save' goes with 'do'");
      s.save = n["save"].Scalar();
    }
    if (n["within"] && s.action != Step::Action::Expect) fail(n["within"], "'within' goes with 'expect'");
    if (n["for"] && s.action != Step::Action::ExpectNot) fail(n["for"], "'for' goes with 'expect_not'");
    if (s.action == Step::Action::Expect) s.window = n["within"] ? duration(n["within"], "within") : kDefaultWithin;
    if (s.action == Step::Action::ExpectNot) {
      if (!n["for"]) fail(n, "'expect_not' needs 'for' (how long it must not happen)");
      s.window = duration(n["for"], "for");
    }
    if (s.action == Step::Action::None && triggers == 0) fail(n, "a step needs a trigger or one of do, expect, expect_not");
    s.name = n["name"] ? n["name"].Scalar() : fmt::format("step {}", index + 1);
    return s;
  }

  Scenario scenario(const YAML::Node& root) const {
    if (!root.IsMap()) fail(root, "a scenario is a map with name, timeout and steps");
    only_keys(root, kScenarioKeys, "the scenario");
    Scenario s;
    s.file = std::string(file_);
    s.name = root["name"] ? root["name"].Scalar() : std::string(file_);
    if (root["timeout"]) s.timeout = duration(root["timeout"], "timeout");
    const YAML::Node steps = root["steps"];
    if (!steps || !steps.IsSequence() || steps.size() == 0) fail(root, "'steps' must be a list of at least one step");
    for (std::size_t i = 0; i < steps.size(); ++i) s.steps.push_back(step(steps[i], i));
    return s;
  }

 private:
  std::string_view file_;
};

}  // namespace

Expected<Nanoseconds, std::string> parse_duration(std::string_view text) {
  struct Unit {
    std::string_view suffix;
    double ns;
  };
  // Longest suffixes first, so "ms" is not read as "s".
  static constexpr std::array<Unit, 5> kUnits = {{{"min", 60e9}, {"ms", 1e6}, {"us", 1e3}, {"ns", 1.0}, {"s", 1e9}}};
  for (const Unit& u : kUnits) {
    if (text.size() <= u.suffix.size() || text.substr(text.size() - u.suffix.size()) != u.suffix) continue;
    const std::string number(text.substr(0, text.size() - u.suffix.size()));
    char* end = nullptr;
    const double v = std::strtod(number.c_str(), &end);
    if (end == number.c_str() || *end != '\0' || !std::isfinite(v) || v < 0 || v * u.ns > 9.0e18) break;
    return Nanoseconds{static_cast<std::int64_t>(std::llround(v * u.ns))};
  }
  return fail(fmt::format("'{}' is not a duration (a number and one of ns, us, ms, s, min: 250ms, 2s)", text));
}

std::string format_duration(Nanoseconds d) {
  const auto ns = d.count();
  if (ns == 0) return "0 ms";
  if (ns % 1'000'000'000 == 0) return fmt::format("{} s", ns / 1'000'000'000);
  if (ns >= 1'000'000'000) return fmt::format("{:.3f} s", static_cast<double>(ns) / 1e9);
  if (ns % 1'000'000 == 0) return fmt::format("{} ms", ns / 1'000'000);
  if (ns >= 1'000'000) return fmt::format("{:.3f} ms", static_cast<double>(ns) / 1e6);
  return fmt::format("{} us", ns / 1000);
}

Expected<Scenario, std::string> parse_scenario(std::string_view text, std::string_view file) {
  Parser parser(file);
  try {
    return parser.scenario(YAML::Load(std::string(text)));
  } catch (const Problem& p) {
    return fail(p.text);
  } catch (const YAML::Exception& e) {
    return fail(fmt::format("{}: {}", parser.where(e.mark), e.msg));
  }
}

Expected<Scenario, std::string> load_scenario(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(fmt::format("{}: cannot open the scenario file", path));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scenario(text.str(), path);
}

}  // namespace ecat::scenario
