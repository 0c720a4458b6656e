// What the master knows about one slave after the scan and configuration.
// Register layouts: ESC datasheet Section II (shared/spec/esc-registers.md §3-§7).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "master/sii.hpp"
#include "master/topology.hpp"

namespace ecat::master {

// AL control/status state codes (ETG.1000.6 §6.4.1; esm-al-codes.md §1).
enum class AlState : std::uint8_t { Init = 0x1, PreOp = 0x2, Boot = 0x3, SafeOp = 0x4, Op = 0x8 };

inline constexpr std::uint8_t kAlStateMask = 0x0F;
inline constexpr std::uint8_t kAlErrorBit = 0x10;     // AL status ErrInd / AL control ack
inline constexpr std::uint8_t kAlIdentBit = 0x20;     // device identification

std::string_view describe(AlState s) noexcept;

// 0x0130 (low byte) and 0x0134 as read in one 6-byte FPRD (SOEM, TwinCAT).
struct AlStatus {
  std::uint16_t raw = 0;
  std::uint16_t code = 0;
  std::uint8_t state() const noexcept { return static_cast<std::uint8_t>(raw & kAlStateMask); }
  bool error() const noexcept { return (raw & kAlErrorBit) != 0; }
  bool is(AlState s) const noexcept { return state() == static_cast<std::uint8_t>(s); }
};

// Registers 0x0000-0x0009 (ESC information, features).
struct EscInfo {
  std::uint8_t type = 0;
  std::uint8_t revision = 0;
  std::uint16_t build = 0;
  std::uint8_t fmmus = 0;
  std::uint8_t sync_managers = 0;
  std::uint8_t ram_kib = 0;
  std::uint8_t port_descriptor = 0;
  std::uint16_t features = 0;
  static constexpr std::uint16_t kFeatureDc = 0x0004;
  static constexpr std::uint16_t kFeatureDc64 = 0x0008;
  static constexpr std::uint16_t kFeatureNoLrw = 0x0200;
  bool has_dc() const noexcept { return (features & kFeatureDc) != 0; }
};

// SM0 (master -> slave) and SM1 (slave -> master) as programmed.
struct MailboxLayout {
  std::uint16_t rx_start = 0, rx_size = 0;  // SM0
  std::uint16_t tx_start = 0, tx_size = 0;  // SM1
  std::uint8_t rx_control = 0x26, tx_control = 0x22;
  bool configured = false;
};

// One process-data SM as the master programs it (SOEM walks every SM of
// type 3/4: masters.md §1.3; a device may have several per direction,
// Beckhoff EK1828 outputs on SM0 and SM1).
struct ProcessSm {
  std::uint8_t sm = 0;
  bool outputs = false;  // type 3 (master -> slave), else type 4
  std::uint16_t start = 0;
  std::uint8_t control = 0;
  std::uint16_t bytes = 0;
  std::uint32_t logical = 0;  // offset in the image, set by configure_process_data()
};

// SM + FMMU programming and the slave's place in the process image.
struct ProcessDataLayout {
  std::uint16_t output_bytes = 0;   // RxPDO (all outputs SMs)
  std::uint16_t input_bytes = 0;    // TxPDO (all inputs SMs)
  std::uint32_t output_offset = 0;  // in the logical image
  std::uint32_t input_offset = 0;
  std::uint16_t sm2_start = 0, sm3_start = 0;
  std::uint8_t sm2_control = 0x64, sm3_control = 0x20;
  std::optional<std::uint32_t> mailbox_status_offset;  // logical byte of SM1 status, if mapped
  bool configured = false;
  // The SMs programmed. With per_sm set (CoeClient::read_pdo_sizes,
  // Master::size_process_data_from_sii) their `bytes` are the sizes asked
  // for and output_bytes/input_bytes their sums; otherwise
  // configure_process_data() makes SM2 (output_bytes) and SM3 (input_bytes).
  std::vector<ProcessSm> sms;
  bool per_sm = false;
  // output_bytes/input_bytes = the sums of the SMs' bytes.
  void sum_sizes() noexcept {
    std::uint32_t out = 0, in = 0;
    for (const ProcessSm& p : sms) (p.outputs ? out : in) += p.bytes;
    output_bytes = static_cast<std::uint16_t>(out);
    input_bytes = static_cast<std::uint16_t>(in);
  }
  // The first SM of a direction as programmed, or null.
  const ProcessSm* first(bool outputs) const noexcept {
    for (const ProcessSm& p : sms) {
      if (p.outputs == outputs) return &p;
    }
    return nullptr;
  }
};

struct DcInfo {
  std::array<std::uint32_t, 4> port_receive_time{};  // 0x0900-0x090F
  std::uint64_t processing_unit_time = 0;             // 0x0918
  std::uint32_t delay_ns = 0;                         // written to 0x0928
  std::int64_t offset_ns = 0;                         // written to 0x0920
};

struct SlaveInfo {
  std::uint16_t position = 0;
  std::uint16_t station_address = 0;
  EscInfo esc;
  std::uint16_t dl_status = 0;
  // Parent, parent port, active and entry ports: from DL status after scan(),
  // entry ports from the port receive times after configure_dc() (topology.hpp).
  SlaveTopology topology;
  AlStatus al;
  std::vector<std::uint8_t> sii_image;
  SiiInfo sii;
  MailboxLayout mailbox;
  std::uint8_t mailbox_counter = 0;  // last counter used, 1..7
  ProcessDataLayout pd;
  DcInfo dc;
};

}  // namespace ecat::master
