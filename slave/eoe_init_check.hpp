// The check of an ENI's EoE InitCmds on the slave side (ecat-slave --eni;
// docs/eoe.md "ENI EoE InitCmds"). The configurator stores a Set IP
// Parameter request per slave; the master sends it over EoE before SafeOp
// (transitions IP, PS) or Op (SO), and the slave answers it like any other
// (coe::EoeServer). The virtual slave does not apply the ENI's values itself,
// as the real device cannot read the ENI either: a master that never sends
// them leaves the slave without the address, as on the real network. When
// the slave enters the state the InitCmd is due by, the fields the ENI sets
// are compared with the slave's EoE IP parameters and one line says whether
// the master set them, and which field differs.
#pragma once

#include <string>
#include <vector>

#include "coe/eoe_server.hpp"
#include "esc/al_status_code.hpp"

namespace ecat::slave {

struct EoeInitExpectation {
  coe::eoe::IpParameters want;  // the fields the InitCmd sets (want.flags) and their values
  esc::AlState due = esc::AlState::SafeOp;  // SafeOp for IP/PS, Op for SO
  std::string where;  // "net.xml:1:4711 (PS)": the InitCmd in the ENI
};

// "applied" or the first differences, for one expectation; `have` is the
// slave's EoE IP parameters when it entered `expectation.due`.
struct EoeInitResult {
  bool applied = false;
  std::string text;
};
EoeInitResult check_eoe_init(const EoeInitExpectation& expectation, const coe::eoe::IpParameters& have);

// IPv4 address as text from the EoE UINT32 (first octet most significant).
std::string ipv4_text(std::uint32_t address);

}  // namespace ecat::slave
