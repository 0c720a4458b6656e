// Reader of an ETG.2100 EtherCAT Network Information file (ENI, the
// EtherCATConfig that TwinCAT and other configurators export): the slaves of
// Config/Slave in bus order with what a virtual chain needs of each: identity
// (Info), mailbox (Mailbox Send/Recv, protocols), process data (ProcessData
// Sm0..Sm7 with their PDO assignment, RxPdo/TxPdo with entries, Send/Recv bit
// ranges), the CoE InitCmds the master sends over the mailbox and the
// register InitCmds, the EoE InitCmds (Set IP Parameter), plus the expected working counter of the cyclic
// commands (Config/Cyclic/Frame/Cmd/Cnt). Errors are LoadError "file:line".
// The reader only reads; esi/eni_devices.hpp turns a network into devices.
#pragma once

#include <array>
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
  SourcePos line;
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
  SourcePos line;
};

// ETG.2100 EoE InitCmd (Mailbox/EoE/InitCmds/InitCmd: Transition, Comment,
// Timeout, Data, Disabled): an EoE request the master sends on the listed
// transitions. Configurators store the Set IP Parameter request there
// (ETG.1000.6 EoE frame type 2): the slave's MAC, IP address, subnet mask,
// default gateway, DNS server and DNS name. Data is taken with the 4-byte
// EoE header (type 2) in front or as the request body alone (UINT32 flags,
// then the flagged fields), whichever its length fits (docs/eoe.md "ENI EoE
// InitCmds"). Addresses as EoE carries them: UINT32, first octet most
// significant (192.168.1.10 = C0A8010Ah).
struct EniEoeIpParameters {
  // ETG.1000.6 Set IP Parameter flags (the same bits as coe::eoe::kHasMac ..).
  static constexpr std::uint32_t kMac = 1u << 0, kIp = 1u << 1, kSubnet = 1u << 2, kGateway = 1u << 3,
                                 kDnsServer = 1u << 4, kDnsName = 1u << 5;
  std::uint32_t flags = 0;
  std::array<std::uint8_t, 6> mac{};
  std::uint32_t ip = 0, subnet = 0, gateway = 0, dns_server = 0;
  std::string dns_name;  // up to 32 bytes, NUL padding removed
};

struct EniEoeInitCmd {
  std::vector<std::string> transitions;
  od::Value data;           // as written
  bool set_ip = false;      // Data is a Set IP Parameter request; `ip` holds it
  EniEoeIpParameters ip;
  std::string comment;
  SourcePos line;
};

struct EniPdoEntry {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t bit_length = 0;
  std::string name;
  std::string data_type;  // ESI base type name ("UINT", "DINT", "BOOL"); may be empty
  SourcePos line;
};

struct EniPdo {
  bool rx = true;
  std::uint16_t index = 0;
  std::string name;
  bool fixed = false;
  std::optional<std::uint8_t> sm;  // PDO@Sm
  std::vector<EniPdoEntry> entries;
  SourcePos line;
};

// ProcessData/SmN.
struct EniSyncManager {
  std::uint8_t number = 0;
  bool outputs = true;  // Type Outputs / Inputs
  std::optional<std::uint16_t> start;
  std::optional<std::uint8_t> control;
  bool enable = true;
  std::vector<std::uint16_t> pdos;  // Pdo children: the assignment
  SourcePos line;
};

struct EniMailbox {
  std::uint16_t out_start = 0;  // Send: master -> slave (SM0)
  std::uint16_t out_length = 0;
  std::uint16_t in_start = 0;   // Recv: slave -> master (SM1)
  std::uint16_t in_length = 0;
  bool coe = false, foe = false, eoe = false, soe = false, aoe = false, voe = false;
  SourcePos line;
};

// ETG.2100 Slave/DC: the distributed-clock set-up the configurator chose.
struct EniDc {
  bool reference_clock = false;
  std::uint32_t cycle_time0 = 0;  // ns, Sync0
  std::uint32_t cycle_time1 = 0;  // ns, Sync1 (0: none)
  std::int32_t shift_time = 0;    // ns
  SourcePos line;
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
  std::vector<EniEoeInitCmd> eoe_init_cmds;
  std::vector<EniRegisterInitCmd> init_cmds;
  std::optional<EniDc> dc;
  SourcePos line;
  SourcePos info_line;
};

struct EniCyclicCmd {
  std::uint8_t cmd = 0;
  std::uint16_t cnt = 0;  // expected working counter
  SourcePos line;
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
