// ENI EoE InitCmds on the slave side (issue 31 item 1; docs/eoe.md "ENI EoE
// InitCmds"): the master sends the configurator's Set IP Parameter request,
// the slave answers it (EoE type 3, result 0) and, on entering SafeOp, says
// whether the master set what the ENI says; a master that skips it is named
// with the field that differs. The slave never applies the ENI's values
// itself. Exact request and response bytes; the real master and chain in one
// process.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "in_process_bus.hpp"
#include "master/coe_client.hpp"
#include "master/mailbox.hpp"
#include "slave/eoe_init_check.hpp"

namespace ecat::master::test {
namespace {

// 192.168.10.2/24, gateway 192.168.10.1: what the ENI's InitCmd sets.
slave::EoeInitExpectation eni_expectation() {
  ecat::slave::EoeInitExpectation x;
  x.want.flags = ecat::coe::eoe::kHasIp | ecat::coe::eoe::kHasSubnet | ecat::coe::eoe::kHasGateway;
  x.want.ip = 0xC0A80A02;
  x.want.subnet = 0xFFFFFF00;
  x.want.gateway = 0xC0A80A01;
  x.due = ecat::slave::EoeInitExpectation{}.due;  // SafeOp: an InitCmd of PS
  x.where = "net.xml:1:812 (PS)";
  return x;
}

struct EoeBus {
  InProcessBus bus;
  std::vector<std::string> reports;
  Master master{bus.transport, bus.clock};

  ::testing::AssertionResult start() {
    auto dev = esi::load_device_file(device_path("generic-servo.xml"));
    if (!dev) return ::testing::AssertionFailure() << dev.error().to_string();
    dev->mailbox.eoe = true;
    ecat::slave::SlaveOptions o;
    o.eoe_init = {eni_expectation()};
    o.report = [this](const std::string& line) { reports.push_back(line); };
    if (auto r = bus.chain().add(std::move(*dev), o); !r) return ::testing::AssertionFailure() << r.error();
    if (master.scan().value_or(0) != 1) return ::testing::AssertionFailure() << "scan";
    if (!master.configure_mailbox(0)) return ::testing::AssertionFailure() << "mailbox";
    if (!master.request_state(0, AlState::PreOp)) return ::testing::AssertionFailure() << "PreOp";
    return ::testing::AssertionSuccess();
  }

  ::testing::AssertionResult to_safe_op() {
    CoeClient coe(master, 0);
    if (!coe.read_pdo_sizes()) return ::testing::AssertionFailure() << "PDO sizes";
    if (!master.configure_process_data()) return ::testing::AssertionFailure() << "process data";
    auto safe = master.request_state(0, AlState::SafeOp);
    if (!safe || !safe->is(AlState::SafeOp)) return ::testing::AssertionFailure() << "SafeOp";
    return ::testing::AssertionSuccess();
  }
};

TEST(EniEoeInit, SetIpParameterFromTheMasterIsAnsweredAndReportedAsApplied) {
  EoeBus b;
  ASSERT_TRUE(b.start());
  // EoE header: frame type 2 (Set IP Parameter request), port 0, last
  // fragment; flags 0Eh (IP, subnet, gateway); the addresses little-endian.
  const std::vector<std::uint8_t> request{0x02, 0x01, 0x00, 0x00, 0x0E, 0x00, 0x00, 0x00, 0x02, 0x0A,
                                          0xA8, 0xC0, 0x00, 0xFF, 0xFF, 0xFF, 0x01, 0x0A, 0xA8, 0xC0};
  ASSERT_TRUE(b.master.mailbox_send(0, mbx::kTypeEoe, request).has_value());
  auto reply = b.master.mailbox_receive(0, std::chrono::milliseconds(100));
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->header.type, mbx::kTypeEoe);
  // Type 3 (Set IP Parameter response), port 0, result 0000h (success).
  EXPECT_EQ(std::vector<std::uint8_t>(reply->payload.begin(), reply->payload.end()),
            (std::vector<std::uint8_t>{0x03, 0x00, 0x00, 0x00}));
  EXPECT_TRUE(b.reports.empty());  // checked on entering SafeOp, not before
  ASSERT_TRUE(b.to_safe_op());
  ASSERT_EQ(b.reports.size(), 1u);
  EXPECT_EQ(b.reports[0],
            "ENI EoE InitCmd net.xml:1:812 (PS): applied by the master before SAFEOP: IP address 192.168.10.2, "
            "subnet mask 255.255.255.0, gateway 192.168.10.1");
  const auto& results = b.bus.chain()[0].firmware().eoe_init_results();
  ASSERT_EQ(results.size(), 1u);
  EXPECT_TRUE(results[0].applied);
}

TEST(EniEoeInit, MasterThatSkipsTheInitCmdIsNamedAndTheSlaveKeepsItsOwnAddress) {
  EoeBus b;
  ASSERT_TRUE(b.start());
  ASSERT_TRUE(b.to_safe_op());
  ASSERT_EQ(b.reports.size(), 1u);
  EXPECT_EQ(b.reports[0],
            "ENI EoE InitCmd net.xml:1:812 (PS): NOT applied by the master before SAFEOP: IP address not set (the "
            "ENI's 192.168.10.2), subnet mask not set (the ENI's 255.255.255.0), gateway not set (the ENI's "
            "192.168.10.1)");
  // Not pre-applied: the slave has no IP, as the real device would not.
  const ecat::coe::eoe::IpParameters& have = b.bus.chain()[0].firmware().coe().eoe().ip_parameters();
  EXPECT_EQ(have.flags & ecat::coe::eoe::kHasIp, 0u);
  EXPECT_EQ(have.ip, 0u);
}

TEST(EniEoeInit, ADifferentAddressIsNamedFieldByField) {
  ecat::slave::EoeInitExpectation x = eni_expectation();
  ecat::coe::eoe::IpParameters have = ecat::coe::eoe::default_parameters();
  have.flags |= ecat::coe::eoe::kHasIp | ecat::coe::eoe::kHasSubnet | ecat::coe::eoe::kHasGateway;
  have.ip = 0xC0A80A03;
  have.subnet = 0xFFFFFF00;
  have.gateway = 0xC0A80A01;
  const auto r = ecat::slave::check_eoe_init(x, have);
  EXPECT_FALSE(r.applied);
  EXPECT_EQ(r.text, "ENI EoE InitCmd net.xml:1:812 (PS): NOT applied by the master before SAFEOP: IP address "
                    "192.168.10.3 (the ENI's 192.168.10.2)");
  x.want.flags = ecat::coe::eoe::kHasMac | ecat::coe::eoe::kHasDnsName;
  x.want.mac = {0x00, 0x01, 0x05, 0x2A, 0x3B, 0x4C};
  x.want.dns_name = {'d', 'r', 'i', 'v', 'e', '1'};
  x.due = ecat::esc::AlState::Op;
  x.where = "net.xml:1:900 (SO)";
  EXPECT_EQ(ecat::slave::check_eoe_init(x, have).text,
            "ENI EoE InitCmd net.xml:1:900 (SO): NOT applied by the master before OP: MAC 02:00:00:00:00:01 (the ENI's "
            "00:01:05:2A:3B:4C), DNS name not set (the ENI's 'drive1')");
}

}  // namespace
}  // namespace ecat::master::test
