#include "esi/twin_judge.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "esi/device_loader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/xml_chars.hpp"
#include "esi/xml_lines.hpp"

namespace ecat::esi {
namespace {

constexpr std::size_t kQuoteBytes = 60;

std::string excerpt(const std::string& s, std::size_t at) {
  const std::size_t from = at > kQuoteBytes / 2 ? at - kQuoteBytes / 2 : 0;
  return s.substr(from, kQuoteBytes);
}

// "" when `a` and `b` are equal, else where they first differ.
std::string difference(const std::string& what, const std::string& a, const std::string& b) {
  if (a == b) return {};
  const auto mm = std::mismatch(a.begin(), a.end(), b.begin(), b.end());
  const auto at = static_cast<std::size_t>(mm.first - a.begin());
  return fmt::format("{}: the writes differ at line {}: '{}' / '{}'", what,
                     LineIndex(a).line_of(static_cast<std::ptrdiff_t>(at)), excerpt(a, at), excerpt(b, at));
}

std::string ill_formed(const std::string& what, const std::string& xml) {
  if (auto at = find_forbidden_xml_char(xml)) {
    return fmt::format("{}: byte {} (line {}) is a character XML 1.0 forbids", what, *at,
                       LineIndex(xml).line_of(static_cast<std::ptrdiff_t>(*at)));
  }
  pugi::xml_document doc;
  const auto r = doc.load_buffer(xml.data(), xml.size());
  if (!r) return fmt::format("{}: not well-formed at byte {}: {}", what, r.offset, r.description());
  return {};
}

}  // namespace

Expected<JudgedTwin, std::string> judge_twin(const od::DeviceDescription& imported) {
  JudgedTwin out;
  const std::string dx1 = write_device_xml(imported);
  if (auto e = ill_formed("device file", dx1); !e.empty()) return fail(e);
  auto l1 = load_device_string(dx1, "device file (1st write)");
  if (!l1) return fail("the loader refuses the device file: " + l1.error().to_string());
  const std::string dx2 = write_device_xml(*l1);
  auto l2 = load_device_string(dx2, "device file (2nd write)");
  if (!l2) return fail("the loader refuses the 2nd device file: " + l2.error().to_string());
  const std::string dx3 = write_device_xml(*l2);
  if (auto e = difference("device file", dx2, dx3); !e.empty()) return fail(e);
  out.first_write_stable = dx1 == dx2;

  const std::string e1 = write_esi(*l1);
  if (auto e = ill_formed("ESI", e1); !e.empty()) return fail(e);
  auto i2 = read_esi_string(e1, "ESI (1st write)");
  if (!i2) return fail("the ESI import refuses the written ESI: " + i2.error().to_string());
  auto l3 = load_device_string(write_device_xml(*i2), "device file of the written ESI");
  if (!l3) return fail("the loader refuses the written ESI's device file: " + l3.error().to_string());
  const std::string e2 = write_esi(*l3);
  if (auto e = difference("ESI", e1, e2); !e.empty()) return fail(e);
  out.device_xml = dx3;
  out.esi = e2;
  return out;
}

}  // namespace ecat::esi
