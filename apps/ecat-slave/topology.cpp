#include "apps/ecat-slave/topology.hpp"

#include <array>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace ecat::app {
namespace {

constexpr unsigned kPorts = 4;  // ports 0..3 of an ESC (Section II 0x0007)

std::vector<std::string> words_of(std::string_view line) {
  std::vector<std::string> out;
  std::istringstream in{std::string(line)};
  for (std::string w; in >> w;) {
    if (w[0] == '#') break;
    out.push_back(w);
  }
  return out;
}

// A time in ns for `cable` / `inner`: decimal, at most one millisecond.
constexpr std::uint32_t kMaxNs = 1'000'000;
std::optional<Nanoseconds> parse_ns(const std::string& text) {
  std::uint32_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc{} || end != text.data() + text.size() || v > kMaxNs) return std::nullopt;
  return Nanoseconds{v};
}

}  // namespace

std::optional<std::size_t> Topology::find(std::string_view name) const {
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    if (slaves[i].name == name) return i;
  }
  return std::nullopt;
}

Expected<SlavePort, std::string> Topology::parse_port(std::string_view text) const {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string_view::npos) return fail(fmt::format("'{}': expected NAME:PORT", text));
  const auto slave = find(text.substr(0, colon));
  if (!slave) return fail(fmt::format("'{}': no slave named '{}'", text, text.substr(0, colon)));
  const std::string_view p = text.substr(colon + 1);
  if (p.size() != 1 || p[0] < '0' || p[0] >= static_cast<char>('0' + kPorts)) {
    return fail(fmt::format("'{}': port must be 0..3", text));
  }
  return SlavePort{*slave, static_cast<unsigned>(p[0] - '0')};
}

Expected<Topology, std::string> parse_topology(std::string_view text, const std::string& source,
                                               const std::string& base_dir) {
  Topology t;
  int number = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++number;
    const auto w = words_of(line);
    if (w.empty()) continue;
    auto error = [&](const std::string& what) { return fmt::format("{}:{}: {}", source, number, what); };
    if (w[0] == "slave") {
      constexpr const char* kSyntax = "expected: slave NAME FILE [at PARENT:PORT [port N]] [cable NS] [inner P F]";
      if (w.size() < 3) return fail(error(kSyntax));
      TopologySlave s;
      s.name = w[1];
      s.line = number;
      if (s.name.find(':') != std::string::npos) return fail(error("a slave name has no ':'"));
      if (t.find(s.name)) return fail(error(fmt::format("slave '{}' defined twice", s.name)));
      const std::filesystem::path file(w[2]);
      s.device_file = file.is_absolute() || base_dir.empty() ? file.string() : (std::filesystem::path(base_dir) / file).string();
      std::size_t at = 3;  // the next word after NAME FILE
      if (at < w.size() && w[at] == "at") {
        if (at + 1 >= w.size()) return fail(error(kSyntax));
        auto parent = t.parse_port(w[at + 1]);
        if (!parent) return fail(error(parent.error()));
        s.parent = parent->slave;
        s.parent_port = parent->port;
        at += 2;
        if (at < w.size() && w[at] == "port") {
          if (at + 1 >= w.size() || w[at + 1].size() != 1 || w[at + 1][0] < '0' || w[at + 1][0] > '3') {
            return fail(error("expected 'port N' with N 0..3"));
          }
          s.port = static_cast<unsigned>(w[at + 1][0] - '0');
          at += 2;
        }
      } else if (!t.slaves.empty()) {
        return fail(error(fmt::format("slave '{}' needs 'at PARENT:PORT' (only the first slave sits on the master)", s.name)));
      }
      while (at < w.size()) {
        const std::size_t values = w[at] == "cable" ? 1 : w[at] == "inner" ? 2 : 0;
        if (values == 0) return fail(error(fmt::format("expected 'at', 'cable' or 'inner', found '{}'", w[at])));
        if (at + values >= w.size()) return fail(error(kSyntax));
        std::array<Nanoseconds, 2> ns{};
        for (std::size_t k = 0; k < values; ++k) {
          auto v = parse_ns(w[at + 1 + k]);
          if (!v) return fail(error(fmt::format("'{}': expected a time in ns (0..{})", w[at + 1 + k], kMaxNs)));
          ns[k] = *v;
        }
        if (values == 1) {
          if (!s.parent) return fail(error("'cable' needs 'at PARENT:PORT' (the master's cable takes 0)"));
          s.cable = ns[0];
        } else {
          s.processing = ns[0];
          s.forwarding = ns[1];
        }
        at += 1 + values;
      }
      // One cable per port: the parent's port and this slave's port are free.
      for (std::size_t i = 0; i < t.slaves.size(); ++i) {
        const TopologySlave& o = t.slaves[i];
        if (s.parent && ((o.parent == s.parent && o.parent_port == s.parent_port) ||
                         (i == *s.parent && o.port == s.parent_port))) {
          return fail(error(fmt::format("port {} of '{}' is already cabled", s.parent_port, t.slaves[*s.parent].name)));
        }
      }
      t.slaves.push_back(std::move(s));
    } else if (w[0] == "redundant") {
      if (w.size() != 2) return fail(error("expected: redundant NAME:PORT"));
      if (t.redundant) return fail(error("the master has one redundant port"));
      auto p = t.parse_port(w[1]);
      if (!p) return fail(error(p.error()));
      t.redundant = *p;
    } else {
      return fail(error(fmt::format("unknown statement '{}' (slave, redundant)", w[0])));
    }
  }
  if (t.slaves.empty()) return fail(fmt::format("{}: no slave", source));
  return t;
}

Expected<Topology, std::string> load_topology(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(fmt::format("{}: cannot open", path));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_topology(text.str(), path, std::filesystem::path(path).parent_path().string());
}

}  // namespace ecat::app
