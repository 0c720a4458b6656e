#include "apps/ecat-master/capture_files.hpp"

#include <cctype>

#include <fmt/format.h>

namespace ecat::app {
namespace {

constexpr unsigned kDefaultNextPort = 1;  // a line slave's outgoing port

}  // namespace

std::string capture_base_name(std::size_t position, const std::string& device_name) {
  std::string name;
  for (char c : device_name) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '_' || c == '-';
    name += keep ? c : '-';
  }
  if (name.empty()) name = "slave";
  return fmt::format("{}-{}", position, name);
}

std::string with_notes_comment(const std::string& xml, const std::vector<std::string>& notes) {
  if (notes.empty()) return xml;
  // "--" may not appear inside an XML comment: the option's name is not spelled out.
  std::string comment = "<!-- captured by ecat-master (capture); what the slave did not say or the file cannot hold:\n";
  for (std::string n : notes) {
    for (std::size_t at = n.find("--"); at != std::string::npos; at = n.find("--", at)) n.replace(at, 2, "- -");
    comment += "  " + n + "\n";
  }
  comment += "-->\n";
  const std::size_t decl_end = xml.starts_with("<?xml") ? xml.find("?>") : std::string::npos;
  if (decl_end == std::string::npos) return comment + xml;
  std::size_t at = decl_end + 2;
  if (at < xml.size() && xml[at] == '\n') ++at;
  return xml.substr(0, at) + comment + xml.substr(at);
}

std::string capture_topology(const std::vector<master::SlaveTopology>& slaves, const std::vector<std::string>& files,
                             std::vector<std::string>& notes) {
  std::string out = "# captured by ecat-master --capture: the cabling the scan found (DL status 0x0110)\n";
  for (std::size_t i = 0; i < slaves.size() && i < files.size(); ++i) {
    const master::SlaveTopology& t = slaves[i];
    out += fmt::format("slave s{} {}", i + 1, files[i]);
    if (i > 0) {
      std::size_t parent = i - 1;
      unsigned port = kDefaultNextPort;
      if (t.parent) {
        parent = *t.parent;
        port = t.parent_port;
      } else {
        notes.push_back(fmt::format("topology: slave {} hangs on the master's second port; placed behind slave {} port {}",
                                    i + 1, i, kDefaultNextPort));
      }
      out += fmt::format(" at s{}:{}", parent + 1, port);
      if (t.entry_port != 0) out += fmt::format(" port {}", t.entry_port);
    }
    out += '\n';
  }
  return out;
}

}  // namespace ecat::app
