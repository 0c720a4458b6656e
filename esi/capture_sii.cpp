// The model of a captured slave from its SII image and ESC registers
// (esi/capture_model.hpp). The SII says what a master configures from
// (identity, names, SMs, FMMUs, mailbox, DC op modes, and the PDOs of a slave
// without CoE); the registers say what the silicon is (type, ports, features).
#include <algorithm>

#include <fmt/format.h>

#include "common/le.hpp"
#include "esi/capture_model.hpp"
#include "esi/capture_process_objects.hpp"
#include "esi/sii_parser.hpp"

namespace ecat::esi {
namespace {

// ESC information registers (ESC datasheet Section II, 0x0000-0x0009).
constexpr std::size_t kRegType = 0x0000, kRegRevision = 0x0001, kRegBuild = 0x0002;
constexpr std::size_t kRegFmmus = 0x0004, kRegSyncManagers = 0x0005, kRegRamKib = 0x0006;
constexpr std::size_t kRegPortDescriptor = 0x0007, kRegFeatures = 0x0008;
constexpr std::uint16_t kFeatureDc = 1u << 2, kFeatureDc64 = 1u << 3;
constexpr std::uint16_t kFeatureNoLrw = 1u << 9, kFeatureNoReadWrite = 1u << 10;
constexpr std::uint32_t kBytesPerKib = 1024;
// Port descriptor 0x0007: two bits per port (00 not implemented, 01 not
// configured, 10 E-bus, 11 MII).
constexpr unsigned kPorts = 4, kPortBits = 2;
constexpr unsigned kPortMask = 0x3, kPortEbus = 0x2, kPortMii = 0x3;

od::FmmuUsage fmmu_usage(std::uint8_t code) {
  switch (code) {
    case sii::kFmmuOutputs: return od::FmmuUsage::Outputs;
    case sii::kFmmuInputs: return od::FmmuUsage::Inputs;
    case sii::kFmmuSyncMStatus: return od::FmmuUsage::MailboxState;
    default: return od::FmmuUsage::Unused;
  }
}

// The largest EEPROM a device file's eepromSize (16 bits) holds in 128-byte units.
constexpr std::size_t kMaxDeviceFileEeprom = 0xFFFF / sii::kBytesPerSizeUnit * sii::kBytesPerSizeUnit;

constexpr std::uint8_t kSmTypeMax = static_cast<std::uint8_t>(od::SmType::Inputs);

void apply_identity(const SiiImage& img, od::DeviceDescription& d) {
  d.identity.vendor_id = img.vendor_id;
  d.identity.product_code = img.product_code;
  d.identity.revision = img.revision;
  d.identity.serial = img.serial;
  if (img.general) {
    d.identity.name = img.string_at(img.general->name_idx);
    d.identity.type_name = img.string_at(img.general->order_idx);
    d.identity.group_type = img.string_at(img.general->group_idx);
  }
}

// The EEPROM size the device file keeps: the size word's, unless the image
// read disagrees (a reader stops at kCaptureMaxSiiBytes; an EEPROM may be
// smaller than its size word says): then the image's, in whole 128-byte units.
std::uint16_t eeprom_size(const SiiImage& img, std::size_t read, std::vector<std::string>& notes) {
  std::size_t bytes = img.eeprom_bytes();
  if (bytes != read) {
    notes.push_back(fmt::format("SII: the size word announces {} bytes, the image read has {}; the device file says {}",
                                bytes, read, read / sii::kBytesPerSizeUnit * sii::kBytesPerSizeUnit));
    bytes = read / sii::kBytesPerSizeUnit * sii::kBytesPerSizeUnit;
  }
  return static_cast<std::uint16_t>(std::min<std::size_t>(bytes, kMaxDeviceFileEeprom));
}

void apply_config(const SiiImage& img, od::DeviceDescription& d, std::vector<std::string>& notes) {
  d.esc.pdi_control = img.config.pdi_control;
  d.esc.pdi_configuration = img.config.pdi_configuration;
  d.esc.sync_impulse_length = img.config.sync_impulse_length;
  d.esc.pdi_configuration2 = img.config.pdi_configuration2;
  d.esc.configured_station_alias = img.config.station_alias;
  if (!img.checksum_ok) notes.push_back("SII: configuration area checksum (word 7) does not match; kept as read");
  d.bootstrap_supported = img.bootstrap_mailbox.receive_size != 0;
  auto& mb = d.mailbox;
  mb.coe = (img.mailbox_protocols & sii::kProtoCoE) != 0;
  mb.foe = (img.mailbox_protocols & sii::kProtoFoE) != 0;
  mb.eoe = (img.mailbox_protocols & sii::kProtoEoE) != 0;
  mb.soe = (img.mailbox_protocols & sii::kProtoSoE) != 0;
  if (!img.general) {
    notes.push_back("SII: no GENERAL category: no names, CoE details and ports; defaults used");
    return;
  }
  const std::uint8_t coe = img.general->coe_details;
  mb.sdo_info = (coe & sii::kCoeSdoInfo) != 0;
  mb.pdo_assign = (coe & sii::kCoePdoAssign) != 0;
  mb.pdo_config = (coe & sii::kCoePdoConfig) != 0;
  mb.pdo_upload = (coe & sii::kCoePdoUpload) != 0;
  mb.complete_access = (coe & sii::kCoeCompleteAccess) != 0;
  d.esc.no_lrw = d.esc.no_lrw || (img.general->flags & sii::kFlagNotLrw) != 0;
}

void apply_layout(const SiiImage& img, od::DeviceDescription& d, std::vector<std::string>& notes) {
  d.sync_managers.clear();
  for (std::size_t n = 0; n < img.sync_managers.size(); ++n) {
    const SiiSyncManager& s = img.sync_managers[n];
    od::SyncManagerConfig c;
    if (s.type > kSmTypeMax) {
      notes.push_back(fmt::format("SII: SM{} has type {}; captured as unused", n, s.type));
    } else {
      c.type = static_cast<od::SmType>(s.type);
    }
    c.start_address = s.start_address;
    c.default_size = s.length;
    c.control = s.control;
    c.enable = (s.enable & sii::kSmEnable) != 0;
    d.sync_managers.push_back(c);
  }
  if (img.sync_managers.empty()) notes.push_back("SII: no SYNCM category: the device file has no sync managers");
  d.fmmus.clear();
  for (std::uint8_t code : img.fmmus) d.fmmus.push_back(fmmu_usage(code));
  d.dc_op_modes.clear();
  for (const SiiDcMode& m : img.dc_modes) {
    od::DcOpMode o;
    o.name = img.string_at(m.name_idx);
    o.description = img.string_at(m.desc_idx);
    o.assign_activate = m.assign_activate;
    o.cycle_time_sync0_factor = m.cycle_time_sync0_factor;
    o.shift_time_sync0 = static_cast<std::int32_t>(m.shift_time_sync0);
    o.cycle_time_sync1_factor = m.cycle_time_sync1_factor;
    o.shift_time_sync1 = static_cast<std::int32_t>(m.shift_time_sync1);
    d.dc_op_modes.push_back(o);
  }
}

// What only the SII says of a PDO the dictionary gave: Mandatory (SII PDO
// flag 0001h, ESI @Mandatory; sii-eeprom.md §3.6) has no CoE object. Without
// it the twin's SII would lose the flag and differ from the image read.
// Fixed stays the dictionary's (SI0 of the mapping object writable or not,
// what the device does), with a note where the SII says otherwise.
void apply_sii_pdo_flags(const SiiImage& img, od::DeviceDescription& d, std::vector<std::string>& notes) {
  for (auto* list : {&d.rx_pdos, &d.tx_pdos}) {
    for (od::Pdo& p : *list) {
      for (const auto* sii_list : {&img.rx_pdos, &img.tx_pdos}) {
        for (const SiiPdo& s : *sii_list) {
          if (s.index != p.index) continue;
          p.mandatory = (s.flags & sii::kPdoMandatory) != 0;
          const bool fixed = (s.flags & sii::kPdoFixed) != 0;
          if (fixed != p.fixed) {
            notes.push_back(fmt::format("PDO {:04X}h: the SII says {}, the mapping object's subindex 0 is {}; captured "
                                        "as the dictionary says",
                                        p.index, fixed ? "fixed" : "not fixed", p.fixed ? "read-only" : "writable"));
          }
        }
      }
    }
  }
}

// GENERAL physical ports (sii-eeprom.md §3.2): 4 bits per port, 1 MII, 3 E-bus;
// the Physics letters Y/K, blank for an unused port (trailing blanks dropped).
constexpr unsigned kSiiPortBits = 4, kSiiPortMask = 0xF, kSiiPortMii = 1, kSiiPortEbus = 3;
std::string physics_of_ports(std::uint16_t ports) {
  std::string physics;
  for (unsigned p = 0; p < kPorts; ++p) {
    const unsigned t = (ports >> (kSiiPortBits * p)) & kSiiPortMask;
    physics += t == kSiiPortMii ? 'Y' : t == kSiiPortEbus ? 'K' : ' ';
  }
  while (!physics.empty() && physics.back() == ' ') physics.pop_back();
  return physics;
}

}  // namespace

void apply_esc_registers(const std::array<std::uint8_t, kEscInfoBytes>& regs, od::DeviceDescription& d) {
  d.esc.esc_type = regs[kRegType];
  d.esc.revision = regs[kRegRevision];
  d.esc.build = load_le<std::uint16_t>(regs.data() + kRegBuild);
  d.esc.fmmu_count = regs[kRegFmmus];
  d.esc.sm_count = regs[kRegSyncManagers];
  d.esc.process_ram_bytes = std::uint32_t{regs[kRegRamKib]} * kBytesPerKib;
  std::string physics;
  for (unsigned p = 0; p < kPorts; ++p) {
    const unsigned t = (regs[kRegPortDescriptor] >> (kPortBits * p)) & kPortMask;
    physics += t == kPortMii ? 'Y' : t == kPortEbus ? 'K' : ' ';
  }
  while (!physics.empty() && physics.back() == ' ') physics.pop_back();
  d.esc.physics = physics;
  const auto features = load_le<std::uint16_t>(regs.data() + kRegFeatures);
  d.esc.dc_supported = (features & kFeatureDc) != 0;
  d.esc.dc_64bit = (features & kFeatureDc64) != 0;
  d.esc.no_lrw = (features & kFeatureNoLrw) != 0;
  d.esc.no_read_write = (features & kFeatureNoReadWrite) != 0;
}

Expected<CaptureResult, std::string> device_from_capture(const CaptureInput& in) {
  auto img = parse_sii(in.sii);
  if (!img) return fail("SII: " + img.error());
  CaptureResult r;
  od::DeviceDescription& d = r.device;
  d.dictionary = od::Dictionary{};
  const bool registers_read = std::any_of(in.esc_info.begin(), in.esc_info.end(), [](std::uint8_t b) { return b != 0; });
  if (registers_read) {
    apply_esc_registers(in.esc_info, d);
  } else {
    r.notes.push_back("ESC registers 0x0000-0x000F not read (all 0): the device file keeps the ESC defaults");
  }
  apply_identity(*img, d);
  apply_config(*img, d, r.notes);
  if (img->general && (!registers_read || d.esc.physics.empty())) {
    std::string from_sii = physics_of_ports(img->general->physical_ports);
    if (!from_sii.empty()) d.esc.physics = std::move(from_sii);
  }
  if (d.esc.physics.empty()) {
    r.notes.push_back("ports: neither the port descriptor (0x0007) nor the SII's GENERAL names one; captured as one MII "
                      "port");
    d.esc.physics = "Y";
  }
  d.esc.eeprom_bytes = eeprom_size(*img, in.sii.size(), r.notes);
  apply_layout(*img, d, r.notes);
  if (d.esc.sm_count < d.sync_managers.size() || d.esc.fmmu_count < d.fmmus.size()) {
    r.notes.push_back(fmt::format("ESC registers: {} SMs and {} FMMUs, the SII describes {} and {}; the SII's counts kept",
                                  d.esc.sm_count, d.esc.fmmu_count, d.sync_managers.size(), d.fmmus.size()));
    d.esc.sm_count = static_cast<std::uint8_t>(std::max<std::size_t>(d.esc.sm_count, d.sync_managers.size()));
    d.esc.fmmu_count = static_cast<std::uint8_t>(std::max<std::size_t>(d.esc.fmmu_count, d.fmmus.size()));
  }
  if (in.dictionary_read) {
    apply_dictionary(in.objects, d, r.notes);
    apply_sii_pdo_flags(*img, d, r.notes);
  } else {
    apply_sii_pdos(*img, d, r.notes);
  }
  return r;
}

}  // namespace ecat::esi
