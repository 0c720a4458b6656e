// A whole device description: identity, ESC layout (sync managers, FMMUs, DC
// op modes, mailbox protocols), PDOs and the object dictionary. Loaded by
// esi/ from our device XML or a vendor ESI; consumed by the ESI/SII writers,
// the CoE layer and the drive. One struct, one source of truth.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/source_pos.hpp"
#include "od/axis_layout.hpp"
#include "od/dictionary.hpp"
#include "od/modular_device.hpp"

namespace ecat::od {

struct Identity {
  std::uint32_t vendor_id = 0;
  std::string vendor_name;
  std::uint32_t product_code = 0;
  std::uint32_t revision = 0;
  std::uint32_t serial = 0;
  std::string name;        // ESI Device/Name, object 1008h
  std::string type_name;   // ESI Device/Type text (order code)
  std::string group_type;  // ESI GroupType
  std::string group_name;
  std::uint32_t device_type = 0;  // object 1000h, e.g. 0x00020192 for a CiA402 servo
  std::string hardware_version;   // 1009h
  std::string software_version;   // 100Ah
  // Identity fields the manual does not give and that the device file marks
  // as placeholders ("vendor_id", "product_code", ...).
  std::vector<std::string> placeholders;
};

// What a sync manager is for (0x1C00 communication types, ETG.1000.6 §5.6.7.4.1).
enum class SmType : std::uint8_t {
  Unused = 0,
  MailboxOut = 1,  // master -> slave (SM0)
  MailboxIn = 2,   // slave -> master (SM1)
  Outputs = 3,     // process data, master -> slave (SM2)
  Inputs = 4,      // process data, slave -> master (SM3)
};

struct SyncManagerConfig {
  SmType type = SmType::Unused;
  std::uint16_t start_address = 0;
  std::uint16_t default_size = 0;  // process-data SMs: 0 means "from the PDOs"
  std::uint8_t control = 0;        // register 0x0804 value
  bool enable = true;
  // Smallest and largest size a master may configure (0 = not limited).
  std::uint16_t min_size = 0;
  std::uint16_t max_size = 0;
};

enum class FmmuUsage : std::uint8_t { Unused, Outputs, Inputs, MailboxState };

struct DcOpMode {
  std::string name;   // "FreeRun", "SM-Synchron", "DC", "DC-Sync01"
  std::string description;
  std::uint16_t assign_activate = 0;  // register 0x0980/0x0981 value
  // Sync0/Sync1 cycle as the ESI gives it: a factor of the master cycle (if
  // positive) or a fixed time in ns; shift in ns.
  std::int32_t cycle_time_sync0_factor = 1;
  std::int32_t shift_time_sync0 = 0;
  std::int32_t cycle_time_sync1_factor = 0;
  std::int32_t shift_time_sync1 = 0;
};

// Limits of the synchronisation modes (1C32h/1C33h sub 4/5 and the ESI's Dc).
struct SyncLimits {
  std::uint32_t min_cycle_time_ns = 125000;
  std::uint32_t max_cycle_time_ns = 0;  // 0 = no limit
  bool free_run = true;
  bool sm_synchronous = true;
  bool dc_sync0 = true;
  bool dc_sync1 = false;
};

struct MailboxProtocols {
  bool coe = true;
  bool foe = false;
  bool eoe = false;
  bool soe = false;
  // CoE details (ESI Mailbox/CoE attributes)
  bool sdo_info = true;
  bool pdo_assign = true;
  bool pdo_config = true;
  bool complete_access = true;
  bool segmented_sdo = true;
  bool pdo_upload = false;
};

struct PdoEntry {
  std::uint16_t index = 0;  // 0 with subindex 0: a gap of bit_length bits
  std::uint8_t subindex = 0;
  std::uint8_t bit_length = 0;
  std::string name;
  DataType type = DataType::Unsigned8;
};

struct Pdo {
  std::uint16_t index = 0;  // 0x1600.. RxPDO, 0x1A00.. TxPDO
  std::string name;
  bool fixed = false;      // mapping cannot be changed
  bool mandatory = false;
  std::optional<std::uint8_t> sm;  // assigned by default to this SM, if any
  std::vector<PdoEntry> entries;
  std::vector<std::uint16_t> excludes;  // PDOs that cannot be assigned together with this one
  SourcePos source_line;  // as Entry::source_line

  bool is_rx() const noexcept { return index >= 0x1600 && index < 0x1800; }
  std::uint32_t bit_length() const noexcept {
    std::uint32_t n = 0;
    for (const auto& e : entries) n += e.bit_length;
    return n;
  }
};

// Properties of the (emulated) ESC silicon that a device file may set.
struct EscProperties {
  std::uint8_t esc_type = 0x02;  // 0x0000 Type: the default reported since the start (ET1100 silicon reports 0x11, ET1200 0x12)
  std::uint8_t revision = 0x00;
  std::uint16_t build = 0x0000;
  std::uint8_t fmmu_count = 8;
  std::uint8_t sm_count = 8;
  std::uint32_t process_ram_bytes = 8 * 1024;
  std::uint16_t eeprom_bytes = 2048;  // SII size (ESI Eeprom/ByteSize)
  bool dc_supported = true;
  bool dc_64bit = true;
  // Commands the ESC does not support (e.g. a device that lacks read-write
  // commands); those datagrams pass with their WKC untouched.
  bool no_lrw = false;
  bool no_read_write = false;  // no APRW/FPRW/BRW
  std::uint16_t pdi_control = 0x0005;      // 0x0140/0x0141 (SII word 0)
  std::uint16_t pdi_configuration = 0;      // 0x0150/0x0151 (SII word 1)
  std::uint16_t sync_impulse_length = 100;  // SII word 2, in 10 ns
  std::uint16_t pdi_configuration2 = 0;     // 0x0152/0x0153 (SII word 3)
  std::uint16_t configured_station_alias = 0;  // SII word 4
  // The ESC's ports as ESI Device@Physics writes them (ETG.2000): one letter
  // per port from port 0, 'Y' (or 'H') MII, 'K' E-bus, ' ' not used; ports
  // past the text are not used. "YY": two MII ports (a line slave); "YKY":
  // a coupler (port 1 to its E-bus terminals); "KKYY": a junction.
  std::string physics = "YY";
};

// CiA 402 facts a drive needs beyond the dictionary.
struct DriveProfile {
  std::uint32_t supported_modes = 0;  // 6502h bits
  std::vector<std::int8_t> homing_methods;
  // Free-form parameters of the simulated motor/plant from the device file
  // (name -> value), read by ds402/.
  std::vector<std::pair<std::string, double>> plant;
  // The CiA 402 axes (logical devices) and where each keeps its objects;
  // one axis unless the device file declares more (<Drive axes>).
  AxisLayout axes;
};

struct DeviceDescription {
  Identity identity;
  EscProperties esc;
  MailboxProtocols mailbox;
  std::vector<SyncManagerConfig> sync_managers;  // index = SM number
  std::vector<FmmuUsage> fmmus;                  // index = FMMU number
  std::vector<DcOpMode> dc_op_modes;
  SyncLimits sync;
  std::vector<Pdo> rx_pdos;  // in index order
  std::vector<Pdo> tx_pdos;
  Dictionary dictionary;
  std::optional<DriveProfile> drive;  // set for CiA 402 devices
  // Set for a modular device (<Modules> in the device file, <Slots> in an ESI):
  // the dictionary and PDOs above already hold its configured modules.
  std::optional<ModularDevice> modular;
  bool bootstrap_supported = false;
  std::string source_file;  // where it was loaded from ("" if built in code)
};

inline bool ModularDevice::placed_pdo(std::uint16_t index) const noexcept {
  for (std::size_t slot = 0; slot < configured.size(); ++slot) {
    if (const ModuleType* t = find(configured[slot])) {
      for (const auto* list : {&t->rx_pdos, &t->tx_pdos}) {
        for (const Pdo& p : *list) {
          if (pdo_at(p.index, slot) == index) return true;
        }
      }
    }
  }
  return false;
}

}  // namespace ecat::od
