// Reader of an ETG.2100 EtherCAT Network Information file (ENI, the
// EtherCATConfig that TwinCAT and other configurators export): the slaves of
// Config/Slave in bus order with what a virtual chain needs of each: identity
// (Info), mailbox (Mailbox Send/Recv, protocols), process data (ProcessData
// Sm0..Sm7 with their PDO assignment, RxPdo/TxPdo with entries, Send/Recv bit
// ranges), the CoE InitCmds the master sends over the mailbox and the
// register InitCmds, plus the expected working counter of the cyclic
// commands (Config/Cyclic/Frame/Cmd/Cnt). Errors are LoadError "file:line".
// The reader only reads; esi/eni_devices.hpp turns a network into devices.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/expected.hpp"
#include "esi/device_error.hpp"
#include "esi/esi_reader.hpp"
#include "od/object.hpp"

namespace ecat::esi {

// ETG.2100 CoE InitCmd (Mailbox/CoE/InitCmds/InitCmd): an SDO download or
// upload the master runs on the listed ESM transitions.
struct EniCoeInitCmd {
  std::vector<std::string> transitions;  // "IP", "PS", "SO", ...
  std::uint8_t ccs = 2;  // as written in the file
  // Whether this is a download. The files disagree on Ccs: ETG.2100's table
  // and SOEM take 2 as a download, configurator exports (TwinCAT's startup
  // list) write 1, the CiA 301 specifier of "initiate download". Decided per
  // file (docs/twins.md "ENI: the Ccs of CoE InitCmds").
  bool download = true;
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  bool complete_access = false;
  od::Value data;
  std::string comment;
  int line = 0;
};

// ETG.2100 register InitCmd (Slave/InitCmds/InitCmd): one datagram.
struct EniRegisterInitCmd {
  std::vector<std::string> transitions;
  std::uint8_t cmd = 0;  // datagram command (ETG.1000.4 Table 13)
  std::uint16_t adp = 0;
  std::uint16_t ado = 0;
  od::Value data;  // Data, or DataLength zero bytes
  std::optional<std::uint16_t> cnt;  // expected working counter
  std::optional<od::Value> validate_data;
  std::optional<od::Value> validate_mask;
  std::string comment;
  int line = 0;
};

struct EniPdoEntry {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t bit_length = 0;
  std::string name;
  std::string data_type;  // ESI base type name ("UINT", "DINT", "BOOL"); may be empty
  int line = 0;
};

struct EniPdo {
  bool rx = true;
  std::uint16_t index = 0;
  std::string name;
  bool fixed = false;
  std::optional<std::uint8_t> sm;  // PDO@Sm
  std::vector<EniPdoEntry> entries;
  int line = 0;
};

// ProcessData/SmN.
struct EniSyncManager {
  std::uint8_t number = 0;
  bool outputs = true;  // Type Outputs / Inputs
  std::optional<std::uint16_t> start;
  std::optional<std::uint8_t> control;
  bool enable = true;
  std::vector<std::uint16_t> pdos;  // Pdo children: the assignment
  int line = 0;
};

struct EniMailbox {
  std::uint16_t out_start = 0;  // Send: master -> slave (SM0)
  std::uint16_t out_length = 0;
  std::uint16_t in_start = 0;   // Recv: slave -> master (SM1)
  std::uint16_t in_length = 0;
  bool coe = false, foe = false, eoe = false, soe = false, aoe = false, voe = false;
  int line = 0;
};

// ETG.2100 Slave/DC: the distributed-clock set-up the configurator chose.
struct EniDc {
  bool reference_clock = false;
  std::uint32_t cycle_time0 = 0;  // ns, Sync0
  std::uint32_t cycle_time1 = 0;  // ns, Sync1 (0: none)
  std::int32_t shift_time = 0;    // ns
  int line = 0;
};

struct EniSlave {
  std::string name;
  std::uint32_t vendor_id = 0;
  std::uint32_t product_code = 0;
  std::uint32_t revision = 0;
  std::uint32_t serial = 0;
  std::optional<std::uint16_t> phys_addr;      // configured station address
  std::optional<std::uint16_t> auto_inc_addr;  // 0, 0xFFFF, 0xFFFE, ...
  std::optional<EniMailbox> mailbox;
  std::vector<EniSyncManager> sync_managers;
  std::vector<EniPdo> rx_pdos, tx_pdos;
  std::optional<std::uint32_t> send_bit_length, recv_bit_length;  // ProcessData Send/Recv
  std::vector<EniCoeInitCmd> coe_init_cmds;
  std::vector<EniRegisterInitCmd> init_cmds;
  std::optional<EniDc> dc;
  int line = 0;
  int info_line = 0;
};

struct EniCyclicCmd {
  std::uint8_t cmd = 0;
  std::uint16_t cnt = 0;  // expected working counter
  int line = 0;
};

struct EniNetwork {
  std::string file;
  std::vector<EniSlave> slaves;
  std::vector<EniCyclicCmd> cyclic;  // every Cyclic/Frame/Cmd, in order
};

Expected<EniNetwork, LoadError> read_eni_string(std::string_view xml, std::string_view name,
                                                std::vector<EsiWarning>* warnings = nullptr);
Expected<EniNetwork, LoadError> read_eni(const std::filesystem::path& path,
                                         std::vector<EsiWarning>* warnings = nullptr);

}  // namespace ecat::esi
