// The conformance suite run in-process: clean against the generic servo, and
// able to fail (a slave that accepts everything, the FakeEsc, fails the
// forbidden-transition cases).
#include "master/conformance/suite.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "esi/esi_writer_device_xml.hpp"
#include "esi/twin_import.hpp"
#include "in_process_bus.hpp"
#include "master_fixture.hpp"
#include "slave/fault_catalogue.hpp"

namespace ecat::master::test {
namespace {

using conformance::Verdict;

// The whole suite against slave 1 of `bus`, on the bus's simulated time, with
// the identity the device file declares.
std::vector<conformance::Report> run_on(InProcessBus& bus, Master& master) {
  conformance::SuiteOptions options;
  options.wait = [&bus](Nanoseconds d) { bus.wait(d); };
  // The power-up register cases (reg.powerup_*): off and on through the
  // fault catalogue (with an SPI PDI the emulated chip powers up too).
  options.power_cycle = [&bus] {
    slave::FaultCatalogue faults(bus.chain());
    auto id = faults.engage({"power_cycle", 0, {}, {}});
    if (!id || !faults.clear(*id)) return false;
    (void)bus.chain().poll(bus.clock.now());
    return true;
  };
  const auto& id = bus.chain()[0].device().identity;
  options.identity = conformance::ExpectedIdentity{id.vendor_id, id.product_code, id.revision};
  return conformance::run_suite(master, options);
}

void expect_no_fail(const std::vector<conformance::Report>& reports) {
  for (const auto& r : reports) {
    EXPECT_NE(r.result.verdict, Verdict::Fail) << r.name << ": expected " << r.result.expected << ", seen "
                                               << r.result.seen;
  }
}

TEST(ConformanceSuite, GenericServoPassesEveryCase) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  Master master(bus.transport, bus.clock);
  const auto reports = run_on(bus, master);
  EXPECT_GT(reports.size(), 50u);
  expect_no_fail(reports);
  for (const auto& r : reports) EXPECT_FALSE(r.clause.empty()) << r.name;
  // The generic servo has every CiA 402 object and 10F3h: none of those cases may skip.
  for (const auto& r : reports) {
    if (r.name.rfind("cia402.", 0) == 0 || r.name.rfind("diag.", 0) == 0) {
      EXPECT_EQ(r.result.verdict, Verdict::Pass) << r.name << ": " << r.result.seen;
    }
  }
  // ECAT_CONFORMANCE_TABLE=1 prints the table (docs/conformance.md).
  if (std::getenv("ECAT_CONFORMANCE_TABLE") != nullptr) std::printf("%s", conformance::format_table(reports).c_str());
  EXPECT_EQ(conformance::failures(reports), 0u);
}

// A device with one byte of outputs (SM2 length 1, which only triggers the
// watchdog, ESC Section II 0x0802): the suite passes and
// config.watchdog_expiry sees SafeOp + ErrInd 0x001B, not Op.
TEST(ConformanceSuite, OneByteOutputsDevicePassesWatchdogExpiry) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(std::string(ECAT_SOURCE_DIR) + "/tests/data/devices/io-8out.xml"));
  Master master(bus.transport, bus.clock);
  const auto reports = run_on(bus, master);
  expect_no_fail(reports);
  bool seen = false;
  for (const auto& r : reports) {
    if (r.name == "config.watchdog_expiry") {
      seen = true;
      EXPECT_EQ(r.result.verdict, Verdict::Pass) << r.result.seen;
    }
  }
  EXPECT_TRUE(seen);
}

// Inovance IS620N (tests/data/esi-vendor/inovance-is620n.xml): its ESI offers
// one OpMode, "DC" (AssignActivate 0x0300), and 1C32h:01 reads 0x0200 (no
// sync mode; the file's DefaultData "0002"), so the drive refuses SafeOp
// without SYNC0 (0x0028). In DC Sync0 mode - SYNC0 programmed before every
// PreOp->SafeOp, as a master following the ESI does - every case passes,
// config.watchdog_expiry seeing the SYNC supervision's 0x001A first.
TEST(ConformanceSuite, DcOnlyDeviceRunsInDcSync0Mode) {
  auto twin = esi::import_twin(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-vendor/inovance-is620n.xml", {});
  ASSERT_TRUE(twin) << twin.error().to_string();
  const std::string file = ::testing::TempDir() + "is620n-" + std::to_string(::getpid()) + ".device.xml";
  std::ofstream(file) << esi::write_device_xml(*twin);
  for (bool dc : {false, true}) {
    InProcessBus bus;
    ASSERT_TRUE(bus.add(file));
    Master master(bus.transport, bus.clock);
    conformance::SuiteOptions options;
    options.wait = [&bus](Nanoseconds d) { bus.wait(d); };
    options.filter = dc ? "" : "esm.preop_to_safeop";
    if (dc) options.dc = conformance::DcSync0{1'000'000, 0, "the ESI offers only DC OpModes"};
    const auto reports = conformance::run_suite(master, options);
    ASSERT_FALSE(reports.empty());
    if (!dc) {
      ASSERT_EQ(reports.size(), 1u);
      EXPECT_EQ(reports[0].result.seen, "PreOp+E 0x0028");
      continue;
    }
    expect_no_fail(reports);
    for (const auto& r : reports) {
      if (r.name == "config.watchdog_expiry") {
        EXPECT_EQ(r.result.seen, "SafeOp+E 0x001A");
      }
      if (r.name == "esm.safeop_to_op") {
        EXPECT_EQ(r.result.seen, "Op");
      }
    }
  }
  std::remove(file.c_str());
}

// A device without process-data SMs (tests/data/esi-mismatch/placeholder-entry.xml:
// one entry-less TxPDO, no Sm) has no 1C12h/1C13h: the SDO aborts 06020000
// are "no PDOs", equal to the SII's none. With an inputs SM in the SII the
// missing 1C13h would be a failure, as before.
TEST(ConformanceSuite, NoAssignmentObjectsWithoutProcessDataSms) {
  auto twin = esi::import_twin(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-mismatch/placeholder-entry.xml", {});
  ASSERT_TRUE(twin) << twin.error().to_string();
  ASSERT_EQ(twin->sync_managers.size(), 2u);
  ASSERT_EQ(twin->dictionary.find(0x1C13), nullptr);
  const std::string file = ::testing::TempDir() + "placeholder-" + std::to_string(::getpid()) + ".device.xml";
  std::ofstream(file) << esi::write_device_xml(*twin);
  InProcessBus bus;
  ASSERT_TRUE(bus.add(file));
  Master master(bus.transport, bus.clock);
  conformance::SuiteOptions options;
  options.wait = [&bus](Nanoseconds d) { bus.wait(d); };
  options.filter = "od.default_pdos_match_sii";
  const auto reports = conformance::run_suite(master, options);
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].result.verdict, Verdict::Pass);
  EXPECT_EQ(reports[0].result.seen, "0x1C12: none; 0x1C13: none; ");
  std::remove(file.c_str());
}

// Issue 18: the same suite with the firmware reaching the ESC over SPI
// framing to an emulated LAN9252 / ET1100 SPI slave (pdi_spi/), every
// transaction within the chip's framing rules.
class ConformanceOverSpi : public testing::TestWithParam<slave::PdiKind> {};

TEST_P(ConformanceOverSpi, GenericServoPassesEveryCase) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml"), 1, GetParam()));
  Master master(bus.transport, bus.clock);
  const auto reports = run_on(bus, master);
  EXPECT_GT(reports.size(), 50u);
  expect_no_fail(reports);
  EXPECT_EQ(conformance::failures(reports), 0u);
  // The power-up cases run over SPI too: the chip is powered up again with
  // the ESC (slave::VirtualSlave::power_on), and the firmware brings it up.
  std::size_t powerup = 0;
  for (const auto& r : reports) {
    if (r.name.rfind("reg.powerup_", 0) != 0) continue;
    ++powerup;
    EXPECT_EQ(r.result.verdict, Verdict::Pass) << r.name << ": " << r.result.seen;
  }
  EXPECT_EQ(powerup, 9u);
  slave::VirtualSlave& s = bus.chain()[0];
  ASSERT_NE(s.spi_pdi(), nullptr);
  EXPECT_FALSE(s.spi_pdi()->failed()) << s.spi_pdi()->error();
  EXPECT_EQ(s.spi_chip()->violations(), 0u);
  EXPECT_GT(s.spi_chip()->transactions(), 1000u);
}

INSTANTIATE_TEST_SUITE_P(Chips, ConformanceOverSpi, testing::Values(slave::PdiKind::Lan9252, slave::PdiKind::Et1100Spi),
                         [](const testing::TestParamInfo<slave::PdiKind>& p) {
                           return p.param == slave::PdiKind::Lan9252 ? std::string("Lan9252") : std::string("Et1100");
                         });

TEST(ConformanceSuite, FilterSelectsCases) {
  EXPECT_TRUE(conformance::matches_filter("esm.init_to_preop", ""));
  EXPECT_TRUE(conformance::matches_filter("esm.init_to_preop", "init_to"));
  EXPECT_TRUE(conformance::matches_filter("sdo.abort_value_range", "sdo.*range"));
  EXPECT_TRUE(conformance::matches_filter("esm.op_to_init", "esm.??_to_init"));
  EXPECT_FALSE(conformance::matches_filter("esm.op_to_init", "sdo.*"));
  EXPECT_FALSE(conformance::matches_filter("esm.op_to_init", "mailbox"));
}

class PermissiveSlave : public MasterFixture {};

// FakeEsc mirrors AL control into AL status with no checks: every forbidden
// transition "succeeds", which the suite must report as failures.
TEST_F(PermissiveSlave, ForbiddenTransitionsAreReportedAsFailures) {
  conformance::SuiteOptions options;
  options.filter = "esm.*_refused";
  auto reports = conformance::run_suite(master, options);
  ASSERT_EQ(reports.size(), 6u);
  EXPECT_EQ(conformance::failures(reports), 6u);
  EXPECT_EQ(reports[0].name, "esm.init_to_safeop_refused");
  EXPECT_EQ(reports[0].result.expected, "Init+E 0x0011");
  EXPECT_EQ(reports[0].result.seen, "SafeOp");
  const std::string table = conformance::format_table(reports);
  EXPECT_NE(table.find("esm.init_to_safeop_refused  FAIL    Init+E 0x0011"), std::string::npos) << table;
  EXPECT_NE(table.find("6 tests, 6 failed, 0 skipped"), std::string::npos);
  const std::string xml = conformance::junit_xml(reports, "suite<&>");
  EXPECT_NE(xml.find("<testsuite name=\"suite&lt;&amp;&gt;\" tests=\"6\" failures=\"6\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("<failure message=\"expected Init+E 0x0011, seen SafeOp\">"), std::string::npos);
  EXPECT_NE(xml.find("name=\"clause\" value=\"ETG.1000.6 §6.4.1, Table 11"), std::string::npos);
}

// A value longer than its column (reg.powerup_fmmus lists 32 registers) is
// wrapped at spaces under its own column; the other rows keep a narrow table.
TEST(ConformanceSuite, LongValuesWrapInTheirOwnColumns) {
  std::string dump;
  for (int i = 0; i < 6; ++i) dump += (i ? " 0x06" : "0x06") + std::to_string(i) + "0=0x0000000000000000";
  std::vector<conformance::Report> reports{
      {"reg.short", "", conformance::CaseResult::pass("PreOp", "PreOp")},
      {"reg.long", "", conformance::CaseResult::failed(dump, "0x0600=0x0000000000000001")},
  };
  const std::string table = conformance::format_table(reports);
  EXPECT_EQ(table,
            "test       result  expected                                  seen\n"
            "---------------------------------------------------------------------\n"
            "reg.short  PASS    PreOp                                     PreOp\n"
            "reg.long   FAIL    0x0600=0x0000000000000000                 0x0600=0x0000000000000001\n"
            "                   0x0610=0x0000000000000000\n"
            "                   0x0620=0x0000000000000000\n"
            "                   0x0630=0x0000000000000000\n"
            "                   0x0640=0x0000000000000000\n"
            "                   0x0650=0x0000000000000000\n"
            "2 tests, 1 failed, 0 skipped\n");
}

TEST(ConformanceSuite, NoSlaveIsOneFailedScanCase) {
  transport::InMemoryTransport empty([](Bytes) {});
  ManualClock clock;
  Master master(empty, clock);
  auto reports = conformance::run_suite(master, {});
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].name, "scan");
  EXPECT_EQ(reports[0].result.verdict, Verdict::Fail);
}

}  // namespace
}  // namespace ecat::master::test
