#include "apps/ecat-master/capture.hpp"

#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "apps/ecat-master/capture_files.hpp"
#include "apps/ecat-master/capture_read.hpp"
#include "apps/ecat-master/error_text.hpp"
#include "esi/atomic_file.hpp"
#include "esi/capture_model.hpp"
#include "esi/device_loader.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/sii_layout.hpp"

namespace ecat::app {
namespace {

Expected<void, std::string> write_text(const std::filesystem::path& path, const std::string& text) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(text.data());
  return esi::write_file_atomic(path, std::span<const std::uint8_t>(p, text.size()));
}

bool has_sdo_info(const master::SiiInfo& sii) {
  return sii.general && (sii.general->coe_details & esi::sii::kCoeSdoInfo) != 0;
}

// The mailbox part: PreOp, the dictionary, back to Init (the state the scan left).
void read_mailbox_slave(master::Master& master, std::size_t i, esi::CaptureInput& in, std::vector<std::string>& notes) {
  const master::SiiInfo& sii = master.slave(i).sii;
  if (!sii.has_coe()) {
    notes.push_back("no CoE: captured from the SII alone (no dictionary beyond the SII's PDO entries)");
    return;
  }
  if (!has_sdo_info(sii)) {
    notes.push_back("CoE without SDO information: captured from the SII alone (no dictionary beyond the SII's PDO entries)");
    return;
  }
  if (auto ok = master.configure_mailbox(i); !ok) {
    notes.push_back(fmt::format("mailbox set-up failed ({}); captured from the SII alone", error_text(ok.error())));
    return;
  }
  auto st = master.request_state(i, master::AlState::PreOp);
  if (!st || st->error()) {
    notes.push_back(fmt::format("PreOp not reached ({}); captured from the SII alone",
                                st ? fmt::format("AL status code 0x{:04X}", st->code) : error_text(st.error())));
  } else {
    read_dictionary(master, i, in, notes);
  }
  if (auto back = master.request_state(i, master::AlState::Init); !back || back->error()) {
    notes.push_back("could not bring the slave back to Init after the capture");
  }
}

}  // namespace

Expected<CaptureSummary, std::string> capture_network(master::Master& master, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return fail(fmt::format("--capture {}: {}", dir, ec.message()));
  auto n = master.scan();
  if (!n) return fail(fmt::format("scan: {}", error_text(n.error())));
  if (*n == 0) return fail("scan found no slave");
  CaptureSummary summary;
  std::vector<std::string> files;
  std::vector<master::SlaveTopology> topology;
  std::string failed;
  for (std::size_t i = 0; i < *n; ++i) {
    const std::string base = capture_base_name(i + 1, master.slave(i).sii.device_name());
    const std::filesystem::path root = std::filesystem::path(dir) / base;
    std::vector<std::string> notes;
    esi::CaptureInput in;
    if (auto ok = read_slave_memory(master, i, in); !ok) {
      failed += fmt::format("slave {}: {}; ", i + 1, ok.error());
      continue;
    }
    read_mailbox_slave(master, i, in, notes);
    auto model = esi::device_from_capture(in);
    if (!model) {
      failed += fmt::format("slave {}: {}; ", i + 1, model.error());
      continue;
    }
    notes.insert(notes.end(), model->notes.begin(), model->notes.end());
    const std::string xml_file = base + ".xml";
    auto xml = esi::write_device_xml(model->device);
    std::string xml_text = with_notes_comment(xml, notes);
    auto written = write_text(root.string() + ".xml", xml_text);
    if (written) written = esi::write_file_atomic(root.string() + ".sii.bin", in.sii);
    if (!written) {
      failed += fmt::format("slave {}: {}; ", i + 1, written.error());
      continue;
    }
    if (auto back = esi::load_device_file(root.string() + ".xml"); !back) {
      notes.push_back("the captured device file does not load: " + back.error().to_string());
    }
    for (const std::string& note : notes) std::fprintf(stderr, "ecat-master: capture: slave %zu (%s): %s\n", i + 1, base.c_str(), note.c_str());
    std::string note_text;
    for (const std::string& note : notes) note_text += note + '\n';
    std::filesystem::remove(root.string() + ".notes.txt", ec);
    if (!notes.empty()) (void)write_text(root.string() + ".notes.txt", note_text);
    summary.notes += notes.size();
    files.push_back(xml_file);
    topology.push_back(master.slave(i).topology);
    std::printf("slave %zu: %s.xml, %s.sii.bin (%zu bytes), %zu object(s), %zu note(s)\n", i + 1, base.c_str(),
                base.c_str(), in.sii.size(), model->device.dictionary.size(), notes.size());
  }
  if (!failed.empty()) return fail("capture incomplete: " + failed.substr(0, failed.size() - 2));
  std::vector<std::string> topo_notes;
  const std::string topo = capture_topology(topology, files, topo_notes);
  for (const std::string& note : topo_notes) std::fprintf(stderr, "ecat-master: capture: %s\n", note.c_str());
  if (auto ok = write_text(std::filesystem::path(dir) / "topology.txt", topo); !ok) return fail(ok.error());
  summary.slaves = *n;
  summary.notes += topo_notes.size();
  return summary;
}

}  // namespace ecat::app
