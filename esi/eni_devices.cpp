#include "esi/eni_devices.hpp"

#include <algorithm>
#include <cctype>
#include <system_error>

#include <fmt/format.h>

#include "esi/device_loader.hpp"
#include "esi/esi_device_list.hpp"

namespace ecat::esi {
namespace {

namespace fs = std::filesystem;

constexpr std::uint16_t kSmAssignFirst = 0x1C10;

struct EsiCandidate {
  fs::path file;
  EsiDeviceEntry entry;
};

// Every device of every *.xml ESI in `dir`, files in name order; files that
// are no ESI are passed over.
std::vector<EsiCandidate> scan_esi_dir(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (e.is_regular_file(ec) && ext == ".xml") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<EsiCandidate> out;
  for (const auto& f : files) {
    auto listed = list_esi_file(f);
    if (!listed) continue;
    for (auto& entry : *listed) out.push_back({f, std::move(entry)});
  }
  return out;
}

// The ENI's layout on a device from an ESI: identity serial, mailbox
// addresses, and the ENI's PDO assignment as the default one (the PDOs'
// sync manager and the 1C1xh defaults), since that is what the configured
// network runs with.
// ETG.2100 Slave/DC and the PS register InitCmd that writes the DC activation
// 0x0980 (AssignActivate): the cycle and shift the configured network runs
// with become the defaults of 1C32h/1C33h:02 (cycle time) and :03 (shift time)
// (ETG.1020 §22.2), what a master reads back from the twin; an AssignActivate
// that none of the ESI's OpModes has is a warning. The sync mode (1C3xh:01) is
// left as the ESI has it: the master's writes select it.
void apply_eni_dc(const EniSlave& s, od::DeviceDescription& d, std::vector<EsiWarning>* warnings) {
  if (!s.dc) return;
  constexpr std::uint16_t kDcActivation = 0x0980;
  constexpr std::uint8_t kCycleTimeSub = 2, kShiftTimeSub = 3;
  constexpr std::uint16_t kSyncOutputs = 0x1C32, kSyncInputs = 0x1C33;
  std::optional<std::uint16_t> assign;
  for (const auto& c : s.init_cmds) {
    const bool ps = std::find(c.transitions.begin(), c.transitions.end(), "PS") != c.transitions.end();
    if (ps && c.ado == kDcActivation && c.data.size() >= 2) {
      assign = static_cast<std::uint16_t>(c.data[0] | (c.data[1] << 8));
    }
  }
  if (assign && *assign != 0 && warnings &&
      std::none_of(d.dc_op_modes.begin(), d.dc_op_modes.end(),
                   [&](const od::DcOpMode& m) { return m.assign_activate == *assign; })) {
    warnings->push_back({"DC", s.dc->line,
                         fmt::format("AssignActivate #x{:04X} (the 0980h InitCmd) is none of the ESI's OpModes", *assign)});
  }
  auto set = [&](std::uint16_t index, std::uint8_t sub, std::uint32_t v) {
    od::Object* o = d.dictionary.find(index);
    od::Entry* e = o ? o->find(sub) : nullptr;
    if (!e || e->bit_length != 32) return;
    e->default_value = {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v >> 16),
                        static_cast<std::uint8_t>(v >> 24)};
  };
  if (s.dc->cycle_time0 == 0) return;
  for (std::uint16_t index : {kSyncOutputs, kSyncInputs}) {
    set(index, kCycleTimeSub, s.dc->cycle_time0);
    set(index, kShiftTimeSub, static_cast<std::uint32_t>(s.dc->shift_time));
  }
}

void apply_eni_layout(const EniSlave& s, od::DeviceDescription& d, std::vector<EsiWarning>* warnings) {
  d.identity.serial = s.serial;
  apply_eni_dc(s, d, warnings);
  auto warn = [&](SourcePos line, std::string element, std::string message) {
    if (warnings) warnings->push_back({std::move(element), line, std::move(message)});
  };
  if (s.mailbox) {
    for (auto& sm : d.sync_managers) {
      if (sm.type == od::SmType::MailboxOut) {
        sm.start_address = s.mailbox->out_start;
        sm.default_size = s.mailbox->out_length;
      } else if (sm.type == od::SmType::MailboxIn) {
        sm.start_address = s.mailbox->in_start;
        sm.default_size = s.mailbox->in_length;
      }
    }
  }
  for (const auto& esm : s.sync_managers) {
    if (esm.number >= d.sync_managers.size()) {
      warn(esm.line, fmt::format("Sm{}", esm.number), "the ESI has no such sync manager; ignored");
      continue;
    }
    auto& sm = d.sync_managers[esm.number];
    const od::SmType want = esm.outputs ? od::SmType::Outputs : od::SmType::Inputs;
    if (sm.type != want) {
      warn(esm.line, fmt::format("Sm{}", esm.number), "the ESI gives this sync manager another type; the ESI's is kept");
      continue;
    }
    if (esm.start) sm.start_address = *esm.start;
    if (esm.control) sm.control = *esm.control;
    auto& pdos = esm.outputs ? d.rx_pdos : d.tx_pdos;
    for (auto& p : pdos) {
      const bool listed = std::find(esm.pdos.begin(), esm.pdos.end(), p.index) != esm.pdos.end();
      if (listed) {
        p.sm = esm.number;
      } else if (p.sm == esm.number) {
        p.sm.reset();
      }
    }
    for (auto index : esm.pdos) {
      if (std::none_of(pdos.begin(), pdos.end(), [&](const od::Pdo& p) { return p.index == index; })) {
        warn(esm.line, "Pdo", fmt::format("PDO #x{:04X} is not in the ESI", index));
      }
    }
    // The default assignment in the dictionary follows (ETG.1000.6 §5.6.7.4.2).
    if (od::Object* o = d.dictionary.find(static_cast<std::uint16_t>(kSmAssignFirst + esm.number))) {
      if (esm.pdos.size() > o->max_subindex()) {
        warn(esm.line, fmt::format("Sm{}", esm.number), "the ESI's assignment object has too few subindices");
        continue;
      }
      for (auto& e : o->entries) {
        if (e.subindex == 0) {
          e.default_value = {static_cast<std::uint8_t>(esm.pdos.size())};
        } else {
          const std::uint16_t v = e.subindex <= esm.pdos.size() ? esm.pdos[e.subindex - 1] : 0;
          e.default_value = {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8)};
        }
      }
    }
  }
}

// Revision matching (decision, docs/twins.md "Networks from an ENI"): the ESI
// with the ENI's revision when the directory has one; otherwise one of the same
// product code whose high revision word (the major, incompatible part in the
// Beckhoff scheme ETG.2000 RevisionNo files follow: 0x0011_0000 = -0017 of the
// description) equals the ENI's - the highest low word not above the ENI's,
// else the lowest above it. Another major revision is never taken.
constexpr unsigned kRevisionWordBits = 16;

std::vector<const EsiCandidate*> esi_candidates_for(const std::vector<EsiCandidate>& esis, const EniSlave& s) {
  std::vector<const EsiCandidate*> exact, below, above;
  for (const auto& c : esis) {
    if (c.entry.product_code != s.product_code) continue;
    if (c.entry.revision == s.revision) {
      exact.push_back(&c);
    } else if (c.entry.revision && (*c.entry.revision >> kRevisionWordBits) == (s.revision >> kRevisionWordBits)) {
      (*c.entry.revision < s.revision ? below : above).push_back(&c);
    }
  }
  std::stable_sort(below.begin(), below.end(),
                   [](const EsiCandidate* a, const EsiCandidate* b) { return *a->entry.revision > *b->entry.revision; });
  std::stable_sort(above.begin(), above.end(),
                   [](const EsiCandidate* a, const EsiCandidate* b) { return *a->entry.revision < *b->entry.revision; });
  exact.insert(exact.end(), below.begin(), below.end());
  exact.insert(exact.end(), above.begin(), above.end());
  return exact;
}

// The device loaded from an ENI slave's synthesised device file keeps, per
// object, entry and PDO, where it stands in that file; the file the user has is
// the ENI (the device's source_file), so each is moved to the ENI element the
// line was written from (a column in a one-line export).
void to_eni_positions(od::DeviceDescription& d, const std::vector<SourcePos>& eni_lines) {
  auto map = [&](SourcePos& p) {
    if (p.line > 0 && static_cast<std::size_t>(p.line) <= eni_lines.size()) {
      p = eni_lines[static_cast<std::size_t>(p.line - 1)];
    } else {
      p = SourcePos{};
    }
  };
  std::vector<std::uint16_t> indices;
  for (const od::Object& o : d.dictionary.objects()) indices.push_back(o.index);
  for (std::uint16_t index : indices) {
    od::Object& o = *d.dictionary.find(index);
    map(o.source_line);
    for (od::Entry& e : o.entries) map(e.source_line);
  }
  for (auto* list : {&d.rx_pdos, &d.tx_pdos}) {
    for (od::Pdo& p : *list) map(p.source_line);
  }
}

}  // namespace

Expected<std::vector<EniDevice>, LoadError> eni_devices(const EniNetwork& net, const fs::path& esi_dir,
                                                        std::vector<EsiWarning>* warnings) {
  std::vector<EsiCandidate> esis;
  if (!esi_dir.empty()) esis = scan_esi_dir(esi_dir);
  std::vector<EniDevice> out;
  for (std::size_t i = 0; i < net.slaves.size(); ++i) {
    const EniSlave& s = net.slaves[i];
    EniDevice dev;
    bool found = false;
    for (const EsiCandidate* cp : esi_candidates_for(esis, s)) {
      const EsiCandidate& c = *cp;
      std::vector<EsiWarning> esi_warnings;
      auto d = read_esi(c.file, EsiSelection{s.product_code, c.entry.revision, c.entry.type}, &esi_warnings);
      if (!d || d->identity.vendor_id != s.vendor_id) continue;
      if (c.entry.revision != s.revision) {
        // The twin is the ENI's device: its SII and 1018h:03 say the ENI's revision.
        constexpr std::uint16_t kIdentity = 0x1018;
        constexpr std::uint8_t kRevisionSub = 3;
        d->identity.revision = s.revision;
        if (od::Object* id = d->dictionary.find(kIdentity)) {
          if (od::Entry* e = id->find(kRevisionSub)) {
            e->default_value.assign(sizeof(s.revision), 0);
            for (std::size_t k = 0; k < sizeof(s.revision); ++k) {
              e->default_value[k] = static_cast<std::uint8_t>(s.revision >> (8 * k));
            }
          }
        }
      }
      if (c.entry.revision != s.revision && warnings) {
        warnings->push_back({"RevisionNo", s.info_line ? s.info_line : s.line,
                             fmt::format("no ESI in the directory has revision #x{:08X}; the dictionary comes from {} "
                                         "revision #x{:08X} (same product code and major revision word {:04X}h: "
                                         "compatible), the SII carries the ENI's revision",
                                         s.revision, c.file.filename().string(), c.entry.revision.value_or(0),
                                         s.revision >> kRevisionWordBits)});
      }
      if (warnings) {
        // The ESI's own import warnings, shown at the ENI slave they serve.
        for (auto& w : esi_warnings) {
          warnings->push_back({w.element, s.line, fmt::format("(ESI {}:{}) {}", c.file.string(), w.line, w.message)});
        }
      }
      dev.device = std::move(*d);
      dev.esi_file = c.file.string();
      apply_eni_layout(s, dev.device, warnings);
      found = true;
      break;
    }
    if (!found) {
      EniDeviceXml x = eni_device_xml(s, warnings);
      if (!x.error.empty()) {
        return fail(LoadError{net.file, x.eni_lines.front(), fmt::format("slave {}: {}", i + 1, x.error)});
      }
      const std::string name = fmt::format("{}#slave{}", net.file, i + 1);
      auto d = load_device_string(x.xml, name);
      if (!d) {
        const LoadError& e = d.error();
        const SourcePos line = e.file == name && e.line > 0 && static_cast<std::size_t>(e.line) <= x.eni_lines.size()
                             ? x.eni_lines[static_cast<std::size_t>(e.line - 1)]
                             : s.line;
        return fail(LoadError{net.file, line, fmt::format("slave {} ({}): {}", i + 1, s.name, e.message)});
      }
      dev.device = std::move(*d);
      dev.device.source_file = net.file;
      to_eni_positions(dev.device, x.eni_lines);
    }
    out.push_back(std::move(dev));
  }
  return out;
}

}  // namespace ecat::esi
