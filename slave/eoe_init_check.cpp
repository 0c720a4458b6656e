#include "slave/eoe_init_check.hpp"

#include <cstring>

#include <fmt/format.h>

namespace ecat::slave {

std::string ipv4_text(std::uint32_t a) {
  return fmt::format("{}.{}.{}.{}", a >> 24, (a >> 16) & 0xFF, (a >> 8) & 0xFF, a & 0xFF);
}

namespace {

std::string mac_text(const coe::eoe::Mac& m) {
  return fmt::format("{:02X}:{:02X}:{:02X}:{:02X}:{:02X}:{:02X}", m[0], m[1], m[2], m[3], m[4], m[5]);
}

std::string dns_text(const std::array<char, coe::eoe::kDnsNameSize>& n) {
  return std::string(n.data(), strnlen(n.data(), n.size()));
}

}  // namespace

EoeInitResult check_eoe_init(const EoeInitExpectation& x, const coe::eoe::IpParameters& have) {
  namespace eoe = coe::eoe;
  std::vector<std::string> set, differ;
  auto field = [&](std::uint32_t flag, const char* name, const std::string& want, const std::string& got, bool same) {
    if (!(x.want.flags & flag)) return;
    set.push_back(fmt::format("{} {}", name, want));
    if (!(have.flags & flag)) {
      differ.push_back(fmt::format("{} not set (the ENI's {})", name, want));
    } else if (!same) {
      differ.push_back(fmt::format("{} {} (the ENI's {})", name, got, want));
    }
  };
  field(eoe::kHasMac, "MAC", mac_text(x.want.mac), mac_text(have.mac), have.mac == x.want.mac);
  field(eoe::kHasIp, "IP address", ipv4_text(x.want.ip), ipv4_text(have.ip), have.ip == x.want.ip);
  field(eoe::kHasSubnet, "subnet mask", ipv4_text(x.want.subnet), ipv4_text(have.subnet), have.subnet == x.want.subnet);
  field(eoe::kHasGateway, "gateway", ipv4_text(x.want.gateway), ipv4_text(have.gateway),
        have.gateway == x.want.gateway);
  field(eoe::kHasDnsServer, "DNS server", ipv4_text(x.want.dns_server), ipv4_text(have.dns_server),
        have.dns_server == x.want.dns_server);
  field(eoe::kHasDnsName, "DNS name", "'" + dns_text(x.want.dns_name) + "'", "'" + dns_text(have.dns_name) + "'",
        dns_text(have.dns_name) == dns_text(x.want.dns_name));
  const std::string state(esc::describe(x.due));
  if (differ.empty()) {
    return {true, fmt::format("ENI EoE InitCmd {}: applied by the master before {}: {}", x.where, state,
                              fmt::join(set, ", "))};
  }
  return {false, fmt::format("ENI EoE InitCmd {}: NOT applied by the master before {}: {}", x.where, state,
                             fmt::join(differ, ", "))};
}

}  // namespace ecat::slave
