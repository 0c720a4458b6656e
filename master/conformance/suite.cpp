#include "master/conformance/suite.hpp"

#include <algorithm>
#include <cstdio>

namespace ecat::master::conformance {

CaseResult CaseResult::pass(std::string expected, std::string seen) {
  return CaseResult{Verdict::Pass, std::move(expected), std::move(seen), {}};
}
CaseResult CaseResult::failed(std::string expected, std::string seen) {
  return CaseResult{Verdict::Fail, std::move(expected), std::move(seen), {}};
}
CaseResult CaseResult::skip(std::string why) { return CaseResult{Verdict::Skip, "", std::move(why), {}}; }
CaseResult CaseResult::compare(std::string expected, std::string seen) {
  const bool same = expected == seen;
  return CaseResult{same ? Verdict::Pass : Verdict::Fail, std::move(expected), std::move(seen), {}};
}

std::string hex(std::uint32_t value, int digits) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%0*X", digits, value);
  return buf;
}

std::string format_status(const AlStatus& s) {
  std::string out;
  switch (s.state()) {
    case 1: out = "Init"; break;
    case 2: out = "PreOp"; break;
    case 3: out = "Boot"; break;
    case 4: out = "SafeOp"; break;
    case 8: out = "Op"; break;
    default: out = "state " + hex(s.state(), 1); break;
  }
  if (s.error()) out += "+E " + hex(s.code, 4);
  return out;
}

namespace {
constexpr unsigned kPrepareCycles = 3;
constexpr unsigned kOpCycles = 5;
// DC set-up as ecat-master --dc does it (apps/ecat-master/session.cpp).
constexpr unsigned kDcDriftIterations = 1000;
constexpr Nanoseconds kSync0StartDelay = std::chrono::milliseconds(20);

std::string describe_error(MasterError e) { return std::string(describe(e)); }

}  // namespace

std::string describe_sdo(const SdoError& e) {
  if (e.from_slave) return "abort " + hex(static_cast<std::uint32_t>(e.code), 8);
  return describe_error(e.cause);
}

void Context::cycle() {
  if (info().pd.configured) (void)master_.exchange_process_data();
}

Expected<void, std::string> Context::prepare_process_data() {
  SlaveInfo& s = info();
  bool sized = false;
  if (s.sii.has_coe()) {
    auto coe_client = coe();
    sized = coe_client.read_pdo_sizes().has_value();
  }
  if (!sized) master_.size_process_data_from_sii(slave());
  if (auto r = master_.configure_process_data(); !r) return fail("process data set-up: " + describe_error(r.error()));
  return program_sync0();
}

void Context::run_until_sync0() {
  if (!options_.dc) return;
  const Nanoseconds period{options_.dc->cycle_ns};
  const auto periods = static_cast<unsigned>(kSync0StartDelay / period) + kOpCycles;
  for (unsigned i = 0; i < periods; ++i) {
    wait(period);
    cycle();
  }
}

Expected<void, std::string> Context::program_sync0() {
  if (!options_.dc) return {};
  if (!dc_configured_) {
    if (auto r = master_.configure_dc(master_.clock().now()); !r) return fail("DC set-up: " + describe_error(r.error()));
    if (auto r = master_.dc_static_drift_compensation(kDcDriftIterations); !r) {
      return fail("DC drift compensation: " + describe_error(r.error()));
    }
    dc_configured_ = true;
  }
  if (auto r = master_.configure_sync0(slave(), options_.dc->cycle_ns, options_.dc->shift_ns, kSync0StartDelay); !r) {
    return fail("SYNC0 set-up: " + describe_error(r.error()));
  }
  return {};
}

Expected<void, std::string> Context::go_to(AlState target) {
  auto st = master_.read_al_status(slave());
  if (!st) return fail("AL status: " + describe_error(st.error()));
  if (st->error()) {
    // An Init request also clears a pending error (esm-al-codes.md §5.2).
    auto a = master_.request_state(slave(), AlState::Init, true);
    if (!a || a->error()) return fail(std::string("acknowledge failed"));
    st = a;
  }
  auto step = [&](AlState s) -> Expected<void, std::string> {
    auto r = master_.request_state(slave(), s);
    if (!r) return fail(std::string("request ") + std::string(describe(s)) + ": " + describe_error(r.error()));
    if (r->error() || !r->is(s)) {
      return fail(std::string("request ") + std::string(describe(s)) + " -> " + format_status(*r));
    }
    return {};
  };
  const auto rank = [](std::uint8_t state) { return state == 8 ? 5 : state; };
  const std::uint8_t want = static_cast<std::uint8_t>(target);
  if (rank(st->state()) >= rank(want)) {
    if (st->state() == want) return {};
    return step(target);  // going down is always allowed
  }
  if (st->is(AlState::Init) || st->is(AlState::Boot)) {
    if (st->is(AlState::Boot)) {
      if (auto r = step(AlState::Init); !r) return r;
    }
    if (target == AlState::Init) return {};
    if (info().sii.has_mailbox()) {
      if (auto r = master_.configure_mailbox(slave()); !r) return fail("mailbox SMs: " + describe_error(r.error()));
    }
    if (auto r = step(AlState::PreOp); !r) return r;
    if (target == AlState::PreOp) return {};
  }
  auto now = master_.read_al_status(slave());
  if (!now) return fail("AL status: " + describe_error(now.error()));
  if (now->is(AlState::PreOp)) {
    if (auto r = prepare_process_data(); !r) return r;
    for (unsigned i = 0; i < kPrepareCycles; ++i) cycle();
    if (auto r = step(AlState::SafeOp); !r) return r;
    if (target == AlState::SafeOp) return {};
  }
  // Valid outputs before Op (esm-al-codes.md §3 SafeOp->Op).
  for (unsigned i = 0; i < kOpCycles; ++i) cycle();
  run_until_sync0();
  if (auto r = master_.write_al_control(slave(), static_cast<std::uint16_t>(AlState::Op)); !r || r->error() ||
      !r->is(AlState::Op)) {
    return fail(std::string("request Op -> ") + (r ? format_status(*r) : describe_error(r.error())));
  }
  return {};
}

bool matches_filter(const std::string& name, const std::string& filter) {
  if (filter.empty()) return true;
  if (const std::size_t comma = filter.find(','); comma != std::string::npos) {  // any of several patterns
    return matches_filter(name, filter.substr(0, comma)) || matches_filter(name, filter.substr(comma + 1));
  }
  if (filter.find_first_of("*?") == std::string::npos) return name.find(filter) != std::string::npos;
  // Glob with '*' and '?'.
  std::size_t n = 0, f = 0, star = std::string::npos, mark = 0;
  while (n < name.size()) {
    if (f < filter.size() && (filter[f] == '?' || filter[f] == name[n])) {
      ++n;
      ++f;
    } else if (f < filter.size() && filter[f] == '*') {
      star = f++;
      mark = n;
    } else if (star != std::string::npos) {
      f = star + 1;
      n = ++mark;
    } else {
      return false;
    }
  }
  while (f < filter.size() && filter[f] == '*') ++f;
  return f == filter.size();
}

std::vector<Case> all_cases() {
  std::vector<Case> all;
  for (auto group : {esm_cases(), config_cases(), mailbox_cases(), sdo_cases(), consistency_cases(), register_cases(),
                     identification_cases(), watchdog_cases(), dc_cases(), sii_rule_cases(), cia402_cases(),
                     emergency_cases(), error_field_cases(), foe_cases(), eoe_cases()}) {
    all.insert(all.end(), group.begin(), group.end());
  }
  return all;
}

std::vector<Report> run_cases(Master& master, const std::vector<Case>& cases, const SuiteOptions& options) {
  std::vector<Report> reports;
  Context ctx(master, options);
  for (const Case& c : cases) {
    if (!matches_filter(c.name, options.filter)) continue;
    Report r{c.name, c.clause, {}};
    const Nanoseconds start = master.clock().now();
    // Every case starts from Init without a pending error.
    if (auto init = ctx.go_to(AlState::Init); !init) {
      r.result = CaseResult::failed("Init before the case", init.error());
    } else {
      r.result = c.run(ctx);
    }
    r.result.duration = master.clock().now() - start;
    reports.push_back(std::move(r));
  }
  (void)ctx.go_to(AlState::Init);
  return reports;
}

std::vector<Report> run_suite(Master& master, const SuiteOptions& options, const std::vector<Case>& extra) {
  auto n = master.scan();
  if (!n || options.slave >= *n) {
    Report r{"scan", "ETG.1000.4 §5.4 (BRD WKC), ETG.1000.6 §5.4 (SII)", {}};
    r.result = CaseResult::failed("slave " + std::to_string(options.slave) + " found",
                                  n ? std::to_string(*n) + " slave(s)" : describe_error(n.error()));
    return {r};
  }
  auto cases = all_cases();
  cases.insert(cases.end(), extra.begin(), extra.end());
  return run_cases(master, cases, options);
}

std::size_t failures(const std::vector<Report>& reports) {
  return static_cast<std::size_t>(std::count_if(reports.begin(), reports.end(),
                                                [](const Report& r) { return r.result.verdict == Verdict::Fail; }));
}

namespace {

// The table stays readable on a terminal: a value longer than its column
// (a register dump of every FMMU, say) is wrapped at spaces onto the lines
// below, in its own column, instead of widening the column for every row.
constexpr std::size_t kExpectedColumnMax = 40;
constexpr std::size_t kSeenColumnMax = 64;

std::vector<std::string> wrap(const std::string& text, std::size_t width) {
  std::vector<std::string> lines;
  std::string line;
  std::size_t i = 0;
  while (i < text.size()) {
    std::size_t end = text.find(' ', i);
    if (end == std::string::npos) end = text.size();
    std::string word = text.substr(i, end - i);
    i = end + 1;
    if (word.empty()) continue;
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      lines.push_back(line);
      line.clear();
    }
    while (word.size() > width) {  // one word longer than the column: cut it
      if (!line.empty()) {
        lines.push_back(line);
        line.clear();
      }
      lines.push_back(word.substr(0, width));
      word.erase(0, width);
    }
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty() || lines.empty()) lines.push_back(line);
  return lines;
}

}  // namespace

std::string format_table(const std::vector<Report>& reports) {
  std::size_t wname = 4, wexp = 8;
  for (const auto& r : reports) {
    wname = std::max(wname, r.name.size());
    wexp = std::max(wexp, std::min(r.result.expected.size(), kExpectedColumnMax));
  }
  auto pad = [](std::string s, std::size_t w) {
    s.resize(std::max(s.size(), w), ' ');
    return s;
  };
  std::string out = pad("test", wname) + "  result  " + pad("expected", wexp) + "  seen\n";
  out += std::string(wname + wexp + 20, '-') + "\n";
  const std::string indent(wname + 2 + 6 + 2, ' ');
  for (const auto& r : reports) {
    const char* v = r.result.verdict == Verdict::Pass ? "PASS" : r.result.verdict == Verdict::Fail ? "FAIL" : "SKIP";
    const auto expected = wrap(r.result.expected, wexp);
    const auto seen = wrap(r.result.seen, kSeenColumnMax);
    for (std::size_t i = 0; i < std::max(expected.size(), seen.size()); ++i) {
      std::string line = i == 0 ? pad(r.name, wname) + "  " + pad(v, 6) + "  " : indent;
      line += pad(i < expected.size() ? expected[i] : "", wexp) + "  " + (i < seen.size() ? seen[i] : "");
      while (!line.empty() && line.back() == ' ') line.pop_back();
      out += line + "\n";
    }
  }
  std::size_t skipped = 0;
  for (const auto& r : reports) skipped += r.result.verdict == Verdict::Skip ? 1 : 0;
  out += std::to_string(reports.size()) + " tests, " + std::to_string(failures(reports)) + " failed, " +
         std::to_string(skipped) + " skipped\n";
  return out;
}

namespace {
std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') {
          out += '?';
        } else {
          out += c;
        }
    }
  }
  return out;
}
}  // namespace

std::string junit_xml(const std::vector<Report>& reports, const std::string& suite_name) {
  std::size_t skipped = 0;
  double total = 0;
  for (const auto& r : reports) {
    skipped += r.result.verdict == Verdict::Skip ? 1 : 0;
    total += std::chrono::duration<double>(r.result.duration).count();
  }
  char time_buf[32];
  std::snprintf(time_buf, sizeof time_buf, "%.6f", total);
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<testsuites>\n  <testsuite name=\"" + xml_escape(suite_name) + "\" tests=\"" +
         std::to_string(reports.size()) + "\" failures=\"" + std::to_string(failures(reports)) +
         "\" errors=\"0\" skipped=\"" + std::to_string(skipped) + "\" time=\"" + time_buf + "\">\n";
  for (const auto& r : reports) {
    std::snprintf(time_buf, sizeof time_buf, "%.6f", std::chrono::duration<double>(r.result.duration).count());
    out += "    <testcase classname=\"" + xml_escape(suite_name) + "\" name=\"" + xml_escape(r.name) + "\" time=\"" +
           time_buf + "\">\n";
    out += "      <properties><property name=\"clause\" value=\"" + xml_escape(r.clause) + "\"/></properties>\n";
    if (r.result.verdict == Verdict::Fail) {
      out += "      <failure message=\"expected " + xml_escape(r.result.expected) + ", seen " +
             xml_escape(r.result.seen) + "\">" + xml_escape(r.clause) + "</failure>\n";
    } else if (r.result.verdict == Verdict::Skip) {
      out += "      <skipped message=\"" + xml_escape(r.result.seen) + "\"/>\n";
    }
    out += "      <system-out>expected: " + xml_escape(r.result.expected) + "; seen: " + xml_escape(r.result.seen) +
           "</system-out>\n";
    out += "    </testcase>\n";
  }
  out += "  </testsuite>\n</testsuites>\n";
  return out;
}

}  // namespace ecat::master::conformance
