#include "scenario/scenario_runner.hpp"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

namespace ecat::scenario {
namespace {

using nlohmann::json;

constexpr std::size_t kEventsPerLook = 1000;
constexpr Nanoseconds kTriggerPeriod = std::chrono::milliseconds(1);

bool same_text(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

// A wanted field against what an event has: a list is any of its values,
// strings compare without case, a map compares the keys it names.
bool field_matches(const json& want, const json& have) {
  if (want.is_array()) {
    return std::any_of(want.begin(), want.end(), [&](const json& w) { return field_matches(w, have); });
  }
  if (want.is_string() && have.is_string()) return same_text(want.get_ref<const std::string&>(), have.get_ref<const std::string&>());
  if (want.is_object() && have.is_object()) {
    for (const auto& [key, value] : want.items()) {
      if (!have.contains(key) || !field_matches(value, have[key])) return false;
    }
    return true;
  }
  return want == have;
}

std::string value_text(const json& v) {
  if (v.is_number_unsigned()) return fmt::format("0x{:X} ({})", v.get<std::uint64_t>(), v.get<std::uint64_t>());
  if (v.is_number_integer()) {
    const auto i = v.get<std::int64_t>();
    return i < 0 ? fmt::format("{}", i) : fmt::format("0x{:X} ({})", i, i);
  }
  return v.dump();
}

}  // namespace

std::string_view describe(StepResult::Status s) noexcept {
  switch (s) {
    case StepResult::Status::Pending: return "PENDING";
    case StepResult::Status::Passed: return "PASS";
    case StepResult::Status::Failed: return "FAIL";
    case StepResult::Status::Skipped: return "SKIP";
  }
  return "?";
}

ScenarioRunner::ScenarioRunner(Scenario scenario, control::RequestHandler& handler, bool sample_events)
    : scenario_(std::move(scenario)), handler_(handler), results_(scenario_.steps.size()) {
  if (sample_events) watcher_ = std::make_unique<control::EventWatcher>(handler_.chain());
}

bool ScenarioRunner::passed() const noexcept {
  return done() && std::all_of(results_.begin(), results_.end(),
                               [](const StepResult& r) { return r.status == StepResult::Status::Passed; });
}

Nanoseconds ScenarioRunner::until_due(Nanoseconds now) const noexcept {
  if (done()) return std::chrono::seconds(1);
  const Step& s = scenario_.steps[current_];
  const bool watching_value = (step_triggered_ && s.action != Step::Action::Do && s.match.kind == Match::Kind::Value) ||
                              (!step_triggered_ && s.when && s.when->kind == Match::Kind::Value);
  if (watching_value) return kValuePeriod;
  Nanoseconds due = kTriggerPeriod;
  if (watcher_) due = std::min(due, std::max(Nanoseconds{0}, next_sample_ - now));
  return due;
}

void ScenarioRunner::poll(Nanoseconds now, std::uint64_t frames) {
  last_ = now;
  if (!started_) {
    started_ = true;
    start_ = now;
    step_began_ = now;
    step_frames_ = frames;
    trigger_cursor_ = handler_.events().next_seq();
    next_sample_ = now;
  }
  if (watcher_ && now >= next_sample_) {
    watcher_->sample(now, handler_.events());
    next_sample_ = now + kSamplePeriod;
  }
  while (!done()) {
    const Step& s = scenario_.steps[current_];
    if (now - start_ > scenario_.timeout) {
      finish(StepResult::Status::Failed, now,
             fmt::format("the scenario's timeout ({}) ran out {}", format_duration(scenario_.timeout),
                         step_triggered_ ? "during this step" : "before this step's trigger"));
      break;
    }
    if (!step_triggered_) {
      if (!triggered(s, now, frames)) break;
      step_triggered_ = true;
      window_began_ = now;
    }
    if (!act(s, now)) break;
    step_frames_ = frames;
  }
}

bool ScenarioRunner::triggered(const Step& s, Nanoseconds now, std::uint64_t frames) {
  // A step without a trigger looks at what came since the step before it
  // acted (the events of its request included); a timed one from its time.
  window_cursor_ = handler_.events().next_seq();
  if (!s.after && !s.at && !s.after_frames && !s.when) {
    window_cursor_ = trigger_cursor_;
    return true;
  }
  if (s.after) return now - step_began_ >= *s.after;
  if (s.at) return now - start_ >= *s.at;
  if (s.after_frames) return frames - step_frames_ >= *s.after_frames;
  if (s.when) {
    if (s.when->kind == Match::Kind::Value) {
      std::string seen;
      bool error = false;
      const bool holds = value_holds(*s.when, &seen, &error);
      if (error) {
        finish(StepResult::Status::Failed, now, "when: " + seen);
        return false;
      }
      return holds;
    }
    auto e = next_event(*s.when, &trigger_cursor_);
    if (!e) return false;
    // What came in the same sample after the trigger belongs to this step.
    window_cursor_ = (*e)["seq"].get<std::uint64_t>() + 1;
    return true;
  }
  return true;
}

bool ScenarioRunner::act(const Step& s, Nanoseconds now) {
  const Nanoseconds since = now - window_began_;
  switch (s.action) {
    case Step::Action::None:
      finish(StepResult::Status::Passed, now, "triggered", window_cursor_);
      return true;
    case Step::Action::Do: {
      std::string missing;
      const json request = fill_in(s.request, &missing);
      if (!missing.empty()) {
        finish(StepResult::Status::Failed, now, missing);
        return true;
      }
      // Events the request itself pushes (fault_engaged) belong to the next step.
      const std::uint64_t before = handler_.events().next_seq();
      const json reply = handler_.handle(request);
      if (reply.contains("error")) {
        finish(StepResult::Status::Failed, now,
               fmt::format("{} refused: {}: {}", request.value("cmd", "?"), reply["error"].value("code", "?"),
                           reply["error"].value("message", "")),
               before);
        return true;
      }
      const json result = reply.value("result", json::object());
      if (!s.save.empty()) saved_[s.save] = result;
      finish(StepResult::Status::Passed, now, fmt::format("{}: {}", request.value("cmd", "?"), result.dump()), before);
      return true;
    }
    case Step::Action::Expect:
    case Step::Action::ExpectNot: {
      const bool expect = s.action == Step::Action::Expect;
      std::optional<json> seen_event;
      bool holds = false;
      std::string seen;
      if (s.match.kind == Match::Kind::Event) {
        seen_event = next_event(s.match, &window_cursor_);
        holds = seen_event.has_value();
        if (holds) seen = seen_event->dump();
      } else {
        bool error = false;
        holds = value_holds(s.match, &seen, &error);
        if (error) {
          finish(StepResult::Status::Failed, now, seen);
          return true;
        }
        last_value_ = seen;
      }
      if (holds) {
        finish(expect ? StepResult::Status::Passed : StepResult::Status::Failed, now,
               fmt::format("{} after {}: {}", expect ? "seen" : "seen, which must not happen,", format_duration(since),
                           seen),
               window_cursor_);
        return true;
      }
      if (since >= s.window) {
        if (expect) {
          finish(StepResult::Status::Failed, now,
                 fmt::format("not seen within {}{}", format_duration(s.window),
                             s.match.kind == Match::Kind::Value ? "; last value " + last_value_ : std::string()));
        } else {
          finish(StepResult::Status::Passed, now, fmt::format("not seen for {}", format_duration(s.window)));
        }
        return true;
      }
      return false;
    }
  }
  return false;
}

std::optional<json> ScenarioRunner::next_event(const Match& m, std::uint64_t* cursor) {
  for (;;) {
    const json batch = handler_.events().since(*cursor, kEventsPerLook);
    const json& events = batch["events"];
    for (const json& e : events) {
      if (field_matches(m.event, e)) {
        *cursor = e["seq"].get<std::uint64_t>() + 1;
        return e;
      }
    }
    *cursor = batch["next"].get<std::uint64_t>();
    if (events.size() < kEventsPerLook) return std::nullopt;
  }
}

bool ScenarioRunner::value_holds(const Match& m, std::string* seen, bool* error) {
  const json reply = handler_.handle(m.read);
  if (reply.contains("error")) {
    *error = true;
    *seen = fmt::format("read refused: {}: {}", reply["error"].value("code", "?"), reply["error"].value("message", ""));
    return false;
  }
  const json value = reply["result"].value("value", json());
  *seen = value_text(value);
  if (m.mask) {
    if (!value.is_number_integer()) {
      *error = true;
      *seen = "a mask needs an integer value, read " + value.dump();
      return false;
    }
    const std::uint64_t v = value.is_number_unsigned() ? value.get<std::uint64_t>()
                                                       : static_cast<std::uint64_t>(value.get<std::int64_t>());
    const std::uint64_t masked = v & *m.mask;
    if (!m.equals.is_null() && masked != m.equals.get<std::uint64_t>()) return false;
    const auto d = static_cast<double>(masked);
    return !(m.min && d < *m.min) && !(m.max && d > *m.max);
  }
  if (!m.equals.is_null() && !field_matches(m.equals, value)) return false;
  if (m.min || m.max) {
    if (!value.is_number()) return false;
    const double v = value.get<double>();
    if (m.min && v < *m.min) return false;
    if (m.max && v > *m.max) return false;
  }
  return true;
}

json ScenarioRunner::fill_in(const json& request, std::string* missing) const {
  if (request.is_object()) {
    json out = json::object();
    for (const auto& [key, value] : request.items()) out[key] = fill_in(value, missing);
    return out;
  }
  if (request.is_array()) {
    json out = json::array();
    for (const json& v : request) out.push_back(fill_in(v, missing));
    return out;
  }
  if (!request.is_string()) return request;
  const std::string& text = request.get_ref<const std::string&>();
  if (text.size() < 4 || text.rfind("${", 0) != 0 || text.back() != '}') return request;
  const std::string ref = text.substr(2, text.size() - 3);
  const auto dot = ref.find('.');
  const std::string name = ref.substr(0, dot);
  const auto it = saved_.find(name);
  if (it == saved_.end()) {
    *missing = fmt::format("{}: no earlier step saved '{}'", text, name);
    return request;
  }
  if (dot == std::string::npos) return it->second;
  const std::string field = ref.substr(dot + 1);
  if (!it->second.is_object() || !it->second.contains(field)) {
    *missing = fmt::format("{}: the result saved as '{}' has no '{}' ({})", text, name, field, it->second.dump());
    return request;
  }
  return it->second[field];
}

void ScenarioRunner::finish(StepResult::Status status, Nanoseconds now, std::string message,
                            std::optional<std::uint64_t> cursor) {
  StepResult& r = results_[current_];
  r.status = status;
  r.ended = now - start_;
  r.message = std::move(message);
  ++current_;
  step_triggered_ = false;
  step_began_ = now;
  trigger_cursor_ = cursor.value_or(handler_.events().next_seq());
  last_value_.clear();
  if (status == StepResult::Status::Failed) {
    for (; current_ < results_.size(); ++current_) {
      results_[current_].status = StepResult::Status::Skipped;
      results_[current_].started = results_[current_].ended = now - start_;
      results_[current_].message = "an earlier step failed";
    }
    return;
  }
  if (current_ < results_.size()) results_[current_].started = now - start_;
}

void ScenarioRunner::abort(Nanoseconds now, const std::string& why) {
  if (!started_ || done()) return;
  last_ = now;
  finish(StepResult::Status::Failed, now, why);
}

std::string ScenarioRunner::summary() const {
  std::string out;
  for (std::size_t i = 0; i < results_.size(); ++i) {
    const Step& s = scenario_.steps[i];
    const StepResult& r = results_[i];
    out += fmt::format("  {:<4} {} ({}:{}) at {}: {}\n", describe(r.status), s.name, scenario_.file, s.line,
                       format_duration(r.ended), r.message);
  }
  const auto failed = std::count_if(results_.begin(), results_.end(),
                                    [](const StepResult& r) { return r.status == StepResult::Status::Failed; });
  out += fmt::format("scenario {}: {} ({} steps, {} failed, {})\n", scenario_.name,
                     passed() ? "passed" : (done() ? "FAILED" : "not finished"), results_.size(), failed,
                     format_duration(elapsed()));
  return out;
}

}  // namespace ecat::scenario
